// Bake throughput, repeated (timings are medians of repeated
// runs with their spread, and the machine is read from the machine).
#include <ctime>
#include <sstream>

#include <tbb/global_control.h>

#include "bench/cubature_bench.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "util/timing.h"

namespace ganzfeld::bench {

std::vector<BakeTiming> run_bake_benchmark(bool quick, int repeats) {
  std::vector<BakeTiming> out;
  const std::vector<int> res = quick ? std::vector<int>{16, 16, 8} : std::vector<int>{64, 64, 32};
  for (const char* spec : {"specular:alpha=8", "specular:alpha=1000"}) {
    BakeTiming timing{spec, res, {}, {}, 0, 0.0};
    const ModelPtr model = parse_model(spec);
    tables::BakeOptions options;
    options.resolution = res;
    options.tolerance = 1e-9;
    for (int threads : {1, 2}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      (threads == 1 ? timing.seconds_1 : timing.seconds_2) = util::time_runs(repeats, [&] {
        const tables::Table table = tables::bake(*model, Law::g, options);
        timing.unconverged = table.unconverged;
        timing.max_error = table.node_error;
      });
    }
    out.push_back(std::move(timing));
  }
  return out;
}

std::string significant(double x, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

std::string today_utc() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[16];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d", &utc);
  return buffer;
}

}  // namespace ganzfeld::bench
