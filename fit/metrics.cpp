#include "fit/metrics.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <tbb/parallel_for.h>

#include "util/error.h"

namespace ganzfeld::fit {

namespace {
/// Samples per parallel block: blocks are summed in their order, so sums do not depend on threads.
constexpr std::size_t kBlock = 4096;
}  // namespace

const char* to_string(Metric metric) { return metric == Metric::ngan ? "ngan" : "log"; }

Metric parse_metric(const std::string& text) {
  if (text == "ngan") return Metric::ngan;
  if (text == "log") return Metric::log;
  throw InputError({"unknown ", Named{"metric"},
                    " '" + text +
                        "'; allowed: ngan (Ngan et al. 2005, cosine-weighted L2), "
                        "log (Low et al. 2012, cosine-weighted log)"});
}

std::vector<double> model_values(const FitData& data, const Model& model) {
  std::vector<double> m(data.size());
  const std::size_t blocks = (data.size() + kBlock - 1) / kBlock;
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const std::size_t begin = b * kBlock, n = std::min(kBlock, data.size() - begin);
    model.f_batch(std::span(data.i).subspan(begin, n), std::span(data.j).subspan(begin, n),
                  std::span(m).subspan(begin, n));
  });
  return m;
}

MetricValues measure(const FitData& data, const std::vector<double>& m) {
  const std::size_t blocks = (data.size() + kBlock - 1) / kBlock;
  struct Sums {
    double weight = 0, squared = 0, data_squared = 0, log_squared = 0;
  };
  std::vector<Sums> partial(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    Sums s;
    for (std::size_t k = b * kBlock; k < std::min(data.size(), (b + 1) * kBlock); ++k) {
      const double w = data.weight[k], c = std::max(data.i[k].z, 0.0), d = data.value[k];
      const double diff = (d - m[k]) * c, log_diff = std::log1p(d * c) - std::log1p(std::max(m[k], 0.0) * c);
      s.weight += w;
      s.squared += w * diff * diff;
      s.data_squared += w * d * d * c * c;
      s.log_squared += w * log_diff * log_diff;
    }
    partial[b] = s;
  });
  Sums total;
  for (const Sums& s : partial) {
    total.weight += s.weight;
    total.squared += s.squared;
    total.data_squared += s.data_squared;
    total.log_squared += s.log_squared;
  }
  MetricValues v;
  if (!(total.weight > 0.0)) return v;
  v.ngan_rms = std::sqrt(total.squared / total.weight);
  v.ngan_relative = total.data_squared > 0.0 ? std::sqrt(total.squared / total.data_squared) : v.ngan_rms;
  v.log_rms = std::sqrt(total.log_squared / total.weight);
  return v;
}

double objective(Metric metric, const MetricValues& values) {
  const double e = metric == Metric::ngan ? values.ngan_relative : values.log_rms;
  return e * e;
}

}  // namespace ganzfeld::fit
