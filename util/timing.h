// The one way ganzfeld measures time: a steady-clock stopwatch, the process's CPU time, the median
// of repeated runs (published timings are medians with their spread; docs/performance.md), and
// the machine they ran on.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

namespace ganzfeld::util {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last restart().
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// CPU seconds the process has used so far, all threads together (std::clock): beside wall time on
/// a machine shared with other work, it says what the work itself cost.
inline double process_cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// The machine, read from it: CPU model (/proc/cpuinfo) and hardware threads.
std::string machine_description();

/// Wall seconds of each of `repeats` (>= 1) runs of `run`, in run order.
inline std::vector<double> time_runs(int repeats, const std::function<void()>& run) {
  std::vector<double> seconds;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const Stopwatch watch;
    run();
    seconds.push_back(watch.seconds());
  }
  return seconds;
}

/// The median of `values` (the mean of the middle two for an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// The q-quantile of `values` (0 <= q <= 1) by nearest rank: the smallest value with at least a
/// fraction q of the values at or below it (q = 0.99: p99); 0 for none.
inline double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size()));
  return values[static_cast<std::size_t>(std::max(1.0, rank)) - 1];
}

}  // namespace ganzfeld::util
