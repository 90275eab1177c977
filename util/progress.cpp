#include "util/progress.h"

#include <unistd.h>
#include <cstdio>
#include <memory>

#include "util/timing.h"

namespace ganzfeld::util {

namespace {
class ProgressBar {
 public:
  explicit ProgressBar(std::string label) : label_(std::move(label)) {}
  void update(std::uint64_t done, std::uint64_t total) {
    const double elapsed = watch_.seconds();
    const double fraction = total ? static_cast<double>(done) / total : 1.0;
    const int percent = static_cast<int>(100.0 * fraction);
    if (percent == last_percent_ && done != total) return;  // redraw at most 101 times
    last_percent_ = percent;
    constexpr int kWidth = 30;
    std::string bar(static_cast<std::size_t>(kWidth * fraction), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%% (%llu/%llu)", label_.c_str(), bar.c_str(), percent,
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total));
    if (fraction > 0.0 && done != total) std::fprintf(stderr, " %.0f s left  ", elapsed * (1.0 - fraction) / fraction);
    if (done == total) std::fprintf(stderr, " %.1f s      \n", elapsed);
    std::fflush(stderr);
  }

 private:
  std::string label_;
  Stopwatch watch_;
  int last_percent_ = -1;
};
}  // namespace

std::function<void(std::uint64_t, std::uint64_t)> progress_bar(const std::string& label, bool quiet) {
  if (quiet || !::isatty(STDERR_FILENO)) return {};
  auto bar = std::make_shared<ProgressBar>(label);
  return [bar](std::uint64_t done, std::uint64_t total) { bar->update(done, total); };
}

}  // namespace ganzfeld::util
