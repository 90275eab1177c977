#include "tables/bake.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
#include <random>

#include <Imath/half.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "models/registry.h"
#include "tables/bspline.h"
#include "tables/sample.h"
#include "tables/to_error.h"
#include "util/error.h"

namespace ganzfeld::tables {

/// The stored number nearest to x (unorm16: the float nearest; its codes need the table's range).
float round_to_encoding(double x, Encoding encoding) noexcept {
  const float f = static_cast<float>(x);
  return encoding == Encoding::half ? static_cast<float>(Imath::half(f)) : f;
}

/// The smallest stored number >= x >= 0 (errors are bounds: they may only round up).
float round_up_to_encoding(double x, Encoding encoding) noexcept {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  if (encoding != Encoding::half) return f;  // unorm16 errors are stored as floats
  Imath::half h(f);
  if (static_cast<float>(h) < f) h.setBits(static_cast<std::uint16_t>(h.bits() + 1));  // next half up (f >= 0)
  return static_cast<float>(h);
}

namespace {

bool cancelled(const BakeCommon& options) { return options.cancel && options.cancel->load(std::memory_order_relaxed); }

std::string gib(std::uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", static_cast<double>(bytes) / (1 << 30));
  return buf;
}

}  // namespace

std::vector<int> parse_resolution(const std::string& text, Law law) {
  const std::size_t axes = law == Law::g ? 3 : 1;
  const std::string form = law == Law::g ? "N or NIxNJxNPHI" : "N";
  const auto bad = [&](const std::string& more = "") {
    return InputError({Named{"res", "'" + text + "'"}, " is not a resolution for law " + std::string(to_string(law)) +
                                                           "; expected " + form + " with integers >= 2" + more});
  };
  std::vector<int> counts;
  std::size_t start = 0;
  while (true) {
    const std::size_t x = text.find('x', start);
    const std::string part = text.substr(start, x == std::string::npos ? std::string::npos : x - start);
    if (part.empty() || part.size() > 9 || part.find_first_not_of("0123456789") != std::string::npos) throw bad();
    counts.push_back(std::stoi(part));
    if (x == std::string::npos) break;
    start = x + 1;
  }
  if (counts.size() == 1) counts.assign(axes, counts[0]);
  if (counts.size() != axes) throw bad();
  for (int c : counts)
    if (c < 2) throw bad(" (each axis needs at least 2 nodes: the first at min, the last at max)");
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

std::uint64_t value_bytes(const Table& table) noexcept {
  return static_cast<std::uint64_t>(table.entries()) * bytes_per_value(table.encoding);
}

std::vector<Axis> bake_axes(Law law, const BakeOptions& options) {
  if (options.lobe) {
    if (law != Law::g) throw InputError(std::string("law ") + to_string(law) + " has no lobe frame; only g does");
    if (!options.mappings.empty())
      throw InputError({Named{"mapping"}, " applies to the cosines frame only, not to lobe axes"});
    if (options.warped) return warped_axes(options.resolution, kWarpedThetaWidths * options.lobe->width);
    return lobe_axes(options.resolution, options.lobe->width);
  }
  if (options.warped)
    throw InputError(
        "the warped frame needs a lobe frame (a model whose lobe peaks at the mirror "
        "direction or at j)");
  return make_axes(law, options.resolution, options.mappings);
}

void throw_if_cancelled(const BakeCommon& options) {
  if (cancelled(options)) throw Cancelled("the bake was cancelled");
}

BakeCommon& common(BakeRequest& request) noexcept {
  return std::visit([](BakeCommon& c) -> BakeCommon& { return c; }, request);
}
const BakeCommon& common(const BakeRequest& request) noexcept {
  return std::visit([](const BakeCommon& c) -> const BakeCommon& { return c; }, request);
}

Table bake(const Model& model, Law law, const BakeRequest& request) {
  if (const TargetBake* target = std::get_if<TargetBake>(&request)) return bake_to_error(model, law, *target);
  return bake_resolution(model, law, std::get<BakeOptions>(request));
}

namespace {

/// Refuses what no bake can do: anisotropic models, bad tolerances, too few nodes for the
/// interpolation, tables over kMaxTableBytes. Returns the axes (bake_axes refuses other laws).
std::vector<Axis> checked_axes(const Model& model, Law law, const BakeOptions& options) {
  if (!model.traits().isotropic)
    throw InputError("model '" + model.spec() +
                     "' is anisotropic; tables over (cos_theta_i, cos_theta_j, phi) exist only for isotropic models");
  if (!std::isfinite(options.tolerance) || !(options.tolerance > 0.0))
    throw InputError("tolerance " + format_number(options.tolerance) + " is not allowed; expected a positive number");
  std::vector<Axis> axes = bake_axes(law, options);  // refuses other laws and counts < 2
  const int fewest = min_count(options.interpolation);
  for (const Axis& a : axes)
    if (a.count < fewest)
      throw InputError("resolution " + resolution_text(options.resolution) + " has " + std::to_string(a.count) +
                       " nodes on axis " + a.name + "; " + to_string(options.interpolation) +
                       " interpolation needs at least " + std::to_string(fewest) + " per axis");
  if (options.filter == Filter::hardware && options.interpolation == Interpolation::catmull_rom)
    throw InputError("hardware filtering is validated for linear and b-spline lookups only, not catmull-rom");
  const std::uint64_t bytes = table_bytes(options.resolution);
  if (bytes > kMaxTableBytes)
    throw InputError("resolution " + resolution_text(options.resolution) + " would need " + std::to_string(bytes) +
                     " bytes (" + gib(bytes) + " GiB); the limit is " + std::to_string(kMaxTableBytes) +
                     " bytes (2 GiB)");
  return axes;
}

/// The table's metadata, with room for its entries.
Table empty_table(const Model& model, Law law, const BakeOptions& options, std::vector<Axis> axes) {
  Table table;
  table.axes = std::move(axes);
  table.law = law;
  table.model = model.spec();
  table.model_content = model.content_digest();
  table.tolerance = options.tolerance;
  table.encoding = options.encoding;
  table.interpolation = options.interpolation;
  table.frame = options.lobe ? (options.warped ? Frame::warped : Frame::lobe) : Frame::cosines;
  table.peak = options.lobe ? options.lobe->peak : PeakKind::mirror;
  table.filter = options.filter;
  if (table.frame == Frame::warped) {
    // A given warp serves a table with as many theta_j nodes as it has samples (tables/frame.h).
    const bool given = options.warp && options.warp->samples.size() == static_cast<std::size_t>(table.axes[0].count);
    table.warp = given ? *options.warp : fit_warp(model, *options.lobe, table.axes[0], options.tolerance);
    table.min_cos_j = kWarpedMinCosJ;
  }
  table.version = GANZFELD_VERSION;
  const std::uint64_t n = entry_count(table.axes);
  table.value.resize(n);
  table.error.resize(n);
  return table;
}

/// The law at a point given in the law's coordinates or in the table's axis coordinates.
struct LawAt {
  const Model& model;
  Law law;
  const Table& table;
  // Law coordinates -> directions. g: (ci, cj, phi) with
  //   i = (sqrt(1 - ci^2), 0, ci),  j = (sqrt(1 - cj^2) cos phi, sqrt(1 - cj^2) sin phi, cj);
  // h: j = (sqrt(1 - cj^2), 0, cj);  a: i = (sqrt(1 - ci^2), 0, ci).
  Estimate law_coordinates(std::span<const double> x, const CubatureOptions& c) const {
    if (law == Law::g) return vignetting(model, direction_from_cos(x[0]), direction_from_cos(x[1], x[2]), c);
    const Vec3 d = direction_from_cos(x[0]);
    return law == Law::h ? darkening(model, d, c) : albedo(model, d, c);
  }
  // Axis coordinates -> the law (lobe and warped frames: the directions of tables/frame.h).
  Estimate axis_coordinates(std::span<const double> y, const CubatureOptions& c) const {
    if (table.frame == Frame::lobe) {
      const auto [i, j] = lobe_directions(table.peak, y[0], y[1], y[2]);
      return vignetting(model, i, j, c);
    }
    if (table.frame == Frame::warped) {
      const auto [i, j] = warped_directions(table.peak, table.warp, table.axes[0], y[0], y[1], y[2]);
      return vignetting(model, i, j, c);
    }
    return law_coordinates(y, c);
  }
  // What a node stores of the law there: g / A(theta_j) for the warped frame, else the law.
  double stored_scale(std::span<const double> y) const {
    return table.frame == Frame::warped ? 1.0 / warp_envelope(table.warp, y[0]) : 1.0;
  }
};

/// Rounds the float values of `table` to 16-bit codes over their range (Unorm16::covering of
/// the smallest and largest value) and adds that rounding to each entry's error bound.
void quantize_unorm16(Table& table) {
  if (table.value.empty()) return;
  const auto [lo, hi] = std::minmax_element(table.value.begin(), table.value.end());
  table.unorm = Unorm16::covering(*lo, *hi);
  for (std::size_t m = 0; m < table.value.size(); ++m) {
    const float v = table.unorm.value(table.unorm.code(table.value[m]));
    const double bound = static_cast<double>(table.error[m]) + std::abs(static_cast<double>(table.value[m]) - v);
    table.value[m] = v;
    table.error[m] = round_up_to_encoding(bound, Encoding::unorm16);
  }
}

/// Bakes every node (in parallel, deterministic): value rounded to the encoding, error = the
/// cubature estimate + that rounding, rounded up. Reports progress; refuses values the encoding
/// cannot hold.
void bake_nodes(Table& table, const LawAt& law_at, const BakeOptions& options, const CubatureOptions& cubature) {
  // Node coordinates per axis, computed once: every entry's node, or a b-spline's count - 2 nodes
  // (tables/bspline.h), from whose values the coefficients are solved below.
  const bool spline = table.interpolation == Interpolation::bspline;
  std::vector<std::vector<double>> nodes;
  for (const Axis& axis : table.axes) {
    if (spline) {
      nodes.push_back(bspline_nodes(axis));
      continue;
    }
    std::vector<double> x(axis.count);
    for (int k = 0; k < axis.count; ++k) x[k] = axis.node(k);
    nodes.push_back(std::move(x));
  }
  // Entry m = (k_0 * n_1 + k_1) * n_2 + k_2 (g) or k (h, a).
  auto entry = [&](std::uint64_t m) -> Estimate {
    if (table.law == Law::g) {
      const std::uint64_t n_1 = nodes[1].size(), n_2 = nodes[2].size();
      const double y[3] = {nodes[0][m / (n_1 * n_2)], nodes[1][(m / n_2) % n_1], nodes[2][m % n_2]};
      Estimate e = law_at.axis_coordinates(y, cubature);
      const double scale = law_at.stored_scale(y);
      e.value *= scale;
      e.error *= scale;
      return e;
    }
    const double y[3] = {nodes[0][m], 0.0, 0.0};  // h, a read y[0] only
    return law_at.axis_coordinates(std::span<const double>(y, 1), cubature);
  };
  std::uint64_t n = 1;
  for (const std::vector<double>& x : nodes) n *= x.size();
  std::vector<double> value(n), error(n);  // the law at the nodes and the cubature's estimates
  std::atomic<long long> unconverged{0};
  std::atomic<bool> out_of_range{false};
  std::atomic<std::uint64_t> done{0};
  std::mutex progress_mutex;
  std::uint64_t reported = 0;
  const std::uint64_t step = std::max<std::uint64_t>(1, n / kProgressSteps);
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, n, 1), [&](const tbb::blocked_range<std::uint64_t>& r) {
    for (std::uint64_t m = r.begin(); m != r.end(); ++m) {
      if (cancelled(options)) return;
      const Estimate e = entry(m);
      value[m] = e.value;
      error[m] = e.error;
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
  throw_if_cancelled(options);
  // A b-spline table stores the spline's coefficients (tables/bspline.h), their error bounds from
  // the nodes'; a warped table's lookup multiplies by A(theta_j), so the bound scales with it.
  if (spline) {
    std::function<double(double)> envelope;
    if (table.frame == Frame::warped)
      envelope = [&table](double theta_j) { return warp_envelope(table.warp, theta_j); };
    Coefficients c = bspline_coefficients(table.axes, value, error, envelope);
    value = std::move(c.value);
    error = std::move(c.error);
  }
  for (std::uint64_t m = 0; m < table.value.size(); ++m) {
    const float v = round_to_encoding(value[m], options.encoding);
    if (!std::isfinite(value[m]) || !std::isfinite(v)) out_of_range = true;
    // The stored error bounds |stored value - true value|: cubature estimate + rounding.
    const double bound = error[m] + std::abs(value[m] - static_cast<double>(v));
    table.value[m] = v;
    table.error[m] = round_up_to_encoding(bound, options.encoding);
  }
  if (out_of_range)
    throw options.encoding == Encoding::half
        ? InputError({"law " + std::string(to_string(table.law)) + " of '" + table.model +
                          "' has values outside the half range (|x| <= 65504); use ",
                      Named{"encoding", "float"}})
        : InputError("law " + std::string(to_string(table.law)) + " of '" + table.model +
                     "' has values outside the float range");
  if (options.encoding == Encoding::unorm16) quantize_unorm16(table);
  table.unconverged = unconverged;
  table.node_error = 0.0;
  for (float e : table.error) table.node_error = std::max(table.node_error, static_cast<double>(e));
}

/// The largest node error a lookup can report, in the law's units: a warped table stores g / A(theta_j),
/// and so its error channel; a lookup blends the errors of the entries whose weight is nonzero at
/// the point and multiplies by A there, so each entry's error counts times the largest A over its
/// support along theta_j (A is smooth, tables/frame.h: taken at kSupportSamples points of it).
constexpr int kSupportSamples = 9;
double node_bound(const Table& table) {
  if (table.frame != Frame::warped) return table.node_error;
  const Axis& theta = table.axes[0];
  const int count = theta.count;
  const bool spline = table.interpolation == Interpolation::bspline;
  // Entry k's support in the index coordinate u: a linear node's two cells; a b-spline
  // coefficient's four (tables/bspline.h: s = 1 + u (count - 3), weight B(s - k), |s - k| < 2).
  std::vector<double> largest_scale(static_cast<std::size_t>(count), 0.0);
  for (int k = 0; k < count; ++k) {
    const double lo = spline ? (k - 3.0) / (count - 3) : (k - 1.0) / (count - 1);
    const double hi = spline ? (k + 1.0) / (count - 3) : (k + 1.0) / (count - 1);
    for (int p = 0; p < kSupportSamples; ++p) {
      const double u = std::clamp(lo + (hi - lo) * p / (kSupportSamples - 1), 0.0, 1.0);
      largest_scale[k] = std::max(largest_scale[k], warp_envelope(table.warp, theta.coordinate(u)));
    }
  }
  const std::size_t plane = table.entries() / count;
  double worst = 0.0;
  for (std::size_t m = 0; m < table.error.size(); ++m)
    worst = std::max(worst, table.error[m] * largest_scale[m / plane]);
  return worst;
}

/// Validation at points the table was not built from, against direct cubature: cell centres
/// (where linear interpolation errs most), at every cell of small tables and at a seeded sample of
/// about 1/16 of the cells of large ones (~6% of the bake), plus options.random_checks seeded
/// random points uniform in the law's coordinates (a b-spline: as many again as centres). Sets the measured and the
/// headline error.
void validate(Table& table, const LawAt& law_at, const BakeOptions& options, const CubatureOptions& check,
              Table* texel_fetch_twin) {
  std::vector<std::uint64_t> cell_counts;
  std::uint64_t cells = 1;
  const int beyond = table.interpolation == Interpolation::bspline ? 2 : 0;  // a b-spline's outer coefficients
  for (const Axis& axis : table.axes) {
    cell_counts.push_back(static_cast<std::uint64_t>(axis.count - 1 - beyond));
    cells *= cell_counts.back();
  }
  const std::uint64_t n = table.value.size();
  const std::uint64_t centres =
      std::min<std::uint64_t>(cells, std::max<std::uint64_t>(kMinInterpolationChecks, n / 16));
  std::vector<std::uint64_t> chosen(centres);
  std::mt19937_64 rng(kInterpolationSeed);
  for (std::uint64_t c = 0; c < centres; ++c)
    chosen[c] = centres == cells ? c : std::uniform_int_distribution<std::uint64_t>(0, cells - 1)(rng);
  // A b-spline errs most away from the cell centres (a cubic's error, and the 8-bit fetches'
  // rounding, peak elsewhere in a cell): as many seeded random points again as it has centres.
  const std::uint64_t random_count =
      options.random_checks + (table.interpolation == Interpolation::bspline ? centres : 0);
  const std::vector<double> random = validation_points(table.law, random_count, kValidationSeed, table.min_cos_j);
  const std::size_t dims = table.axes.size();
  const std::uint64_t checks = centres + random_count;
  std::vector<double> check_error(checks, 0.0);
  std::vector<double> exact_weights_error(checks, 0.0);  // the full-precision lookup alone
  // A hardware-filtered table's bound holds for full-precision, nearest-rounded and truncated
  // 8-bit weights alike: the worst of the three lookups is what is measured.
  const std::vector<WeightRounding> roundings =
      table.filter == Filter::hardware
          ? std::vector<WeightRounding>{WeightRounding::exact, WeightRounding::nearest, WeightRounding::truncate}
          : std::vector<WeightRounding>{WeightRounding::exact};
  tbb::parallel_for(std::uint64_t{0}, checks, [&](std::uint64_t c) {
    if (cancelled(options)) return;
    std::vector<double> y(dims);
    if (c < centres) {
      std::uint64_t rest = chosen[c];
      for (std::size_t d = dims; d-- > 0;) {
        const std::uint64_t k = rest % cell_counts[d];
        rest /= cell_counts[d];
        y[d] = table.axes[d].coordinate((static_cast<double>(k) + 0.5) / static_cast<double>(cell_counts[d]));
      }
      if (table.min_cos_j > 0.0 && std::cos(y[0]) < table.min_cos_j) return;  // outside the validated domain
      const Estimate exact = law_at.axis_coordinates(y, check);
      for (WeightRounding r : roundings) {
        const double e = std::abs(sample_axes(table, y, r).value - exact.value) + exact.error;
        check_error[c] = std::max(check_error[c], e);
        if (r == WeightRounding::exact) exact_weights_error[c] = e;
      }
    } else {
      const std::span<const double> x(random.data() + (c - centres) * dims, dims);
      const Estimate exact = law_at.law_coordinates(x, check);
      for (WeightRounding r : roundings) {
        const double e = std::abs(sample(table, x, r).value - exact.value) + exact.error;
        check_error[c] = std::max(check_error[c], e);
        if (r == WeightRounding::exact) exact_weights_error[c] = e;
      }
    }
  });
  throw_if_cancelled(options);
  auto finish = [&](Table& t, const std::vector<double>& errors) {
    t.interpolation_checks = static_cast<long long>(checks);
    t.interpolation_error = 0.0;
    for (double e : errors) t.interpolation_error = std::max(t.interpolation_error, e);
    t.lookup_error = std::max(kLookupMargin * t.interpolation_error, node_bound(t));
  };
  if (texel_fetch_twin) {
    *texel_fetch_twin = table;
    texel_fetch_twin->filter = Filter::texel_fetch;
    finish(*texel_fetch_twin, exact_weights_error);
  }
  finish(table, check_error);
}

}  // namespace

Table bake_resolution(const Model& model, Law law, const BakeOptions& options, Table* texel_fetch_twin) {
  Table table = empty_table(model, law, options, checked_axes(model, law, options));
  const LawAt law_at{model, law, table};
  CubatureOptions cubature;
  cubature.abs_tol = options.tolerance;
  cubature.max_evaluations = options.max_evaluations;
  cubature.cancel = options.cancel;
  bake_nodes(table, law_at, options, cubature);
  CubatureOptions check = cubature;
  if (options.check_tolerance > 0.0) check.abs_tol = options.check_tolerance;
  validate(table, law_at, options, check, options.filter == Filter::hardware ? texel_fetch_twin : nullptr);
  return table;
}

std::vector<double> validation_points(Law law, std::uint64_t count, std::uint64_t seed, double min_cos_j) {
  const std::size_t dims = law == Law::g ? 3 : 1;
  std::vector<double> x;
  x.reserve(count * dims);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::uint64_t p = 0; p < count; ++p) {
    if (law == Law::g) {
      x.push_back(-1.0 + 2.0 * unit(rng));
      x.push_back(min_cos_j + (1.0 - min_cos_j) * unit(rng));
      x.push_back(std::numbers::pi * unit(rng));
    } else {
      x.push_back(unit(rng));
    }
  }
  return x;
}

}  // namespace ganzfeld::tables
