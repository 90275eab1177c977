#include "tables/bake.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <random>

#include <Imath/half.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "util/error.h"
#include "laws/registry.h"
#include "tables/sample.h"

namespace ganzfeld::tables {

namespace {

/// The stored number nearest to x.
float round_to_encoding(double x, Encoding encoding) noexcept {
  const float f = static_cast<float>(x);
  return encoding == Encoding::half ? static_cast<float>(Imath::half(f)) : f;
}

/// The smallest stored number >= x >= 0 (errors are bounds: they may only round up).
float round_up_to_encoding(double x, Encoding encoding) noexcept {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  if (encoding == Encoding::single) return f;
  Imath::half h(f);
  if (static_cast<float>(h) < f) h.setBits(static_cast<std::uint16_t>(h.bits() + 1));  // next half up (f >= 0)
  return static_cast<float>(h);
}

std::string gib(std::uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", static_cast<double>(bytes) / (1 << 30));
  return buf;
}

}  // namespace

std::vector<int> parse_resolution(const std::string& text, Law law) {
  const std::size_t axes = law == Law::g ? 3 : 1;
  const std::string form = law == Law::g ? "N or NIxNJxNPHI" : "N";
  const std::string bad = "--res '" + text + "' is not a resolution for law " + to_string(law) + "; expected " + form +
                          " with integers >= 2";
  std::vector<int> counts;
  std::size_t start = 0;
  while (true) {
    const std::size_t x = text.find('x', start);
    const std::string part = text.substr(start, x == std::string::npos ? std::string::npos : x - start);
    if (part.empty() || part.size() > 9 || part.find_first_not_of("0123456789") != std::string::npos)
      throw InputError(bad);
    counts.push_back(std::stoi(part));
    if (x == std::string::npos) break;
    start = x + 1;
  }
  if (counts.size() == 1) counts.assign(axes, counts[0]);
  if (counts.size() != axes) throw InputError(bad);
  for (int c : counts)
    if (c < 2) throw InputError(bad + " (each axis needs at least 2 nodes: the first at min, the last at max)");
  return counts;
}

std::string resolution_text(const std::vector<int>& resolution) {
  std::string s;
  for (std::size_t d = 0; d < resolution.size(); ++d) {
    if (d) s += 'x';
    s += std::to_string(resolution[d]);
  }
  return s;
}

std::uint64_t table_bytes(const std::vector<int>& resolution) noexcept {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t bytes = kBytesPerEntry;
  for (int c : resolution) {
    if (c <= 0) return 0;
    const auto n = static_cast<std::uint64_t>(c);
    if (bytes > kMax / n) return kMax;
    bytes *= n;
  }
  return bytes;
}

Table bake(const Model& model, Law law, const BakeOptions& options) {
  if (!model.traits().isotropic)
    throw InputError("model '" + model.spec() +
                     "' is anisotropic; tables over (cos_theta_i, cos_theta_j, phi) exist only for isotropic models");
  if (!std::isfinite(options.tolerance) || !(options.tolerance > 0.0))
    throw InputError("tolerance " + format_number(options.tolerance) + " is not allowed; expected a positive number");
  Table table;
  table.axes = make_axes(law, options.resolution, options.mappings);  // refuses other laws and counts < 2
  const std::uint64_t bytes = table_bytes(options.resolution);
  if (bytes > kMaxTableBytes)
    throw InputError("resolution " + resolution_text(options.resolution) + " would need " + std::to_string(bytes) +
                     " bytes (" + gib(bytes) + " GiB); the limit is " + std::to_string(kMaxTableBytes) + " bytes (2 GiB)");
  const std::uint64_t n = entry_count(table.axes);
  table.law = law;
  table.model = model.spec();
  table.model_content = model.content_digest();
  table.tolerance = options.tolerance;
  table.encoding = options.encoding;
  table.version = GANZFELD_VERSION;
  table.value.resize(n);
  table.error.resize(n);

  // Node coordinates per axis, computed once.
  std::vector<std::vector<double>> nodes;
  for (const Axis& axis : table.axes) {
    std::vector<double> x(axis.count);
    for (int k = 0; k < axis.count; ++k) x[k] = axis.node(k);
    nodes.push_back(std::move(x));
  }

  CubatureOptions cubature;
  cubature.abs_tol = options.tolerance;
  cubature.max_evaluations = options.max_evaluations;
  std::atomic<long long> unconverged{0};
  std::atomic<bool> out_of_range{false};
  std::atomic<std::uint64_t> done{0};
  std::mutex progress_mutex;
  std::uint64_t reported = 0;
  const std::uint64_t step = std::max<std::uint64_t>(1, n / kProgressSteps);

  // Axis coordinates -> directions. g: (ci, cj, phi) with
  //   i = (sqrt(1 - ci^2), 0, ci),  j = (sqrt(1 - cj^2) cos phi, sqrt(1 - cj^2) sin phi, cj);
  // h: j = (sqrt(1 - cj^2), 0, cj);  a: i = (sqrt(1 - ci^2), 0, ci).
  auto law_at = [&](std::span<const double> x) -> Estimate {
    if (law == Law::g)
      return vignetting(model, direction_from_cos(x[0]), direction_from_cos(x[1], x[2]), cubature);
    const Vec3 d = direction_from_cos(x[0]);
    return law == Law::h ? darkening(model, d, cubature) : albedo(model, d, cubature);
  };
  // Entry m = (k_i * n_j + k_j) * n_phi + k_phi (g) or k (h, a).
  auto entry = [&](std::uint64_t m) -> Estimate {
    if (law == Law::g) {
      const std::uint64_t n_j = nodes[1].size(), n_phi = nodes[2].size();
      const double x[3] = {nodes[0][m / (n_j * n_phi)], nodes[1][(m / n_phi) % n_j], nodes[2][m % n_phi]};
      return law_at(x);
    }
    const double x[3] = {nodes[0][m], 0.0, 0.0};  // h, a read x[0] only
    return law_at(std::span<const double>(x, 1));
  };

  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, n, 1), [&](const tbb::blocked_range<std::uint64_t>& r) {
    for (std::uint64_t m = r.begin(); m != r.end(); ++m) {
      const Estimate e = entry(m);
      const float v = round_to_encoding(e.value, options.encoding);
      if (!std::isfinite(e.value) || !std::isfinite(v)) out_of_range = true;
      // The stored error bounds |stored value - true value|: cubature estimate + rounding.
      const double bound = e.error + std::abs(e.value - static_cast<double>(v));
      table.value[m] = v;
      table.error[m] = round_up_to_encoding(bound, options.encoding);
      if (!e.converged) ++unconverged;
      const std::uint64_t d = ++done;
      if (options.progress && (d % step == 0 || d == n)) {
        std::lock_guard lock(progress_mutex);
        if (d > reported) {
          reported = d;
          options.progress(d, n);
        }
      }
    }
  });
  if (out_of_range)
    throw InputError("law " + std::string(to_string(law)) + " of '" + table.model + "' has values outside the " +
                     (options.encoding == Encoding::half ? "half range (|x| <= 65504); use --encoding float"
                                                         : "float range"));
  table.unconverged = unconverged;
  table.max_error = 0.0;
  for (float e : table.error) table.max_error = std::max(table.max_error, static_cast<double>(e));

  // Interpolation check: lookups at cell centres (where multilinear interpolation errs most)
  // against cubature, at every cell of small tables and at a seeded sample of about 1/16 of the
  // cells of large ones (~6% of the bake).
  std::vector<std::uint64_t> cell_counts;
  std::uint64_t cells = 1;
  for (const Axis& axis : table.axes) {
    cell_counts.push_back(static_cast<std::uint64_t>(axis.count - 1));
    cells *= cell_counts.back();
  }
  const std::uint64_t checks = std::min<std::uint64_t>(cells, std::max<std::uint64_t>(kMinInterpolationChecks, n / 16));
  std::vector<std::uint64_t> chosen(checks);
  std::mt19937_64 rng(kInterpolationSeed);
  for (std::uint64_t c = 0; c < checks; ++c)
    chosen[c] = checks == cells ? c : std::uniform_int_distribution<std::uint64_t>(0, cells - 1)(rng);
  std::vector<double> check_error(checks);
  tbb::parallel_for(std::uint64_t{0}, checks, [&](std::uint64_t c) {
    std::vector<double> x(table.axes.size());
    std::uint64_t rest = chosen[c];
    for (std::size_t d = table.axes.size(); d-- > 0;) {
      const std::uint64_t k = rest % cell_counts[d];
      rest /= cell_counts[d];
      x[d] = table.axes[d].coordinate((static_cast<double>(k) + 0.5) / static_cast<double>(cell_counts[d]));
    }
    const Estimate exact = law_at(x);
    check_error[c] = std::abs(sample(table, x).value - exact.value) + exact.error;
  });
  table.interpolation_checks = static_cast<long long>(checks);
  table.interpolation_error = 0.0;
  for (double e : check_error) table.interpolation_error = std::max(table.interpolation_error, e);
  return table;
}

}  // namespace ganzfeld::tables
