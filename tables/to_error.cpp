#include "tables/to_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "models/registry.h"
#include "tables/bspline.h"
#include "tables/frame.h"
#include "tables/sample.h"
#include "util/error.h"

namespace ganzfeld::tables {

namespace {

/// Initial node counts (g: 17x17x9; h, a: 33): cheap, and fine enough that the per-axis
/// estimates of the first bake are in their asymptotic regime for smooth laws.
std::vector<int> initial_counts(Law law) { return law == Law::g ? std::vector<int>{17, 17, 9} : std::vector<int>{33}; }

/// The share of E a linear-only search aims its next bake at (the rest absorbs the estimate's slack),
/// and the most it grows an axis in one step (8x the entries in 3-D): a coarse first bake far from
/// E must not jump to a table of millions of nodes on one extrapolation.
constexpr double kLinearAim = 0.9;
constexpr double kLinearMaxGrowth = 2.0;

/// The order of an interpolation's error: linear ~ h^2, Catmull–Rom ~ h^3, the b-spline ~ h^4.
double order(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::catmull_rom: return 3.0;
    case Interpolation::bspline: return 4.0;
    case Interpolation::linear: break;
  }
  return 2.0;
}

/// Step 3 of the search: per axis d, the largest |value at an odd node - interpolation from the
/// even nodes along d| (a grid twice as coarse along d), times 2^-p: that axis' share of the
/// interpolation error at the current spacing. The cubics (Catmull–Rom, the b-spline) at the
/// midpoint of a coarse cell are (-1, 9, 9, -1)/16 of the even nodes k-3, k-1, k+1, k+3; linear
/// (1, 1)/2 of k-1, k+1. A b-spline table's values are coefficients: the law at its nodes is
/// taken from the spline there (tables/bspline.h).
std::vector<double> axis_error_estimates(const Table& table, Interpolation interpolation) {
  const std::size_t dims = table.axes.size();
  std::vector<double> out(dims, 0.0);
  const bool spline = table.interpolation == Interpolation::bspline;
  std::vector<Axis> grid = table.axes;  // the nodes' grid: a b-spline's has count - 2 per axis
  if (spline)
    for (Axis& a : grid) a.count -= 2;
  const std::vector<std::size_t> stride = axis_strides(grid);
  const std::vector<double> value =
      spline ? bspline_node_values(table) : std::vector<double>(table.value.begin(), table.value.end());
  const std::size_t n = value.size();
  const bool cubic = interpolation != Interpolation::linear;
  for (std::size_t d = 0; d < dims; ++d) {
    const int count = grid[d].count;
    const std::size_t s = stride[d];
    double worst = 0.0;
    for (std::size_t m = 0; m < n; ++m) {
      const int k = static_cast<int>((m / s) % count);
      if (k % 2 == 0) continue;
      double predicted;
      if (cubic) {
        if (k < 3 || k + 3 > count - 1) continue;
        predicted = (-value[m - 3 * s] + 9.0 * value[m - s] + 9.0 * value[m + s] - value[m + 3 * s]) / 16.0;
      } else {
        if (k + 1 > count - 1) continue;
        predicted = 0.5 * (value[m - s] + value[m + s]);
      }
      worst = std::max(worst, std::abs(value[m] - predicted));
    }
    out[d] = worst * std::pow(2.0, -order(interpolation));
  }
  return out;
}

/// How far a hardware filter's 8-bit weights may move a lookup of `table`: per axis the largest
/// step between neighbouring nodes over kFilterWeightSteps (a weight truncated to a multiple of
/// 1/256 moves a linear blend by at most its step / 256: tables/sample.h, filter_weight), summed
/// over the axes. Unlike interpolation's h^2, it falls only as h.
double weight_rounding_reach(const Table& table) {
  const std::size_t dims = table.axes.size();
  const std::vector<std::size_t> stride = axis_strides(table.axes);
  double reach = 0.0;
  for (std::size_t d = 0; d < dims; ++d) {
    double step = 0.0;
    for (std::size_t m = 0; m < table.entries(); ++m)
      if ((m / stride[d]) % table.axes[d].count != 0)
        step = std::max(step, std::abs(static_cast<double>(table.value[m]) - table.value[m - stride[d]]));
    reach += step / kFilterWeightSteps;
  }
  return reach;
}

std::uint64_t bytes_of(const std::vector<int>& counts, Encoding encoding) {
  double n = 1.0;
  for (int c : counts) n *= c;
  n *= bytes_per_value(encoding);
  return n > 1.8e19 ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(n);
}

/// Counts that bring each axis' share (calibrated estimate x (h_new/h)^p) to `share`.
std::vector<int> counts_for(const std::vector<int>& counts, const std::vector<double>& estimates, double calibration,
                            double share, Interpolation interpolation) {
  const double fewest = std::max(4, min_count(interpolation));  // the search starts every axis at >= 4
  std::vector<int> out(counts.size());
  for (std::size_t d = 0; d < counts.size(); ++d) {
    const double e = calibration * estimates[d];
    const double factor = e > 0.0 ? std::pow(e / share, 1.0 / order(interpolation)) : 0.5;
    const double cells = std::ceil((counts[d] - 1) * std::max(factor, 0.5));  // shrink at most by half per step
    out[d] = static_cast<int>(std::clamp(cells + 1.0, fewest, 1e9));
  }
  return out;
}

/// `counts` shrunk by one common factor per axis (the shape the estimates chose, at least `fewest` nodes
/// per axis) until the table fits `cap` value bytes: where the predicted counts overshoot the
/// cap, the largest table of that shape within it is the best the search can still bake.
std::vector<int> fit_to_cap(std::vector<int> counts, Encoding encoding, std::uint64_t cap, int fewest) {
  while (bytes_of(counts, encoding) > cap) {
    const double ratio = std::pow(static_cast<double>(cap) / static_cast<double>(bytes_of(counts, encoding)),
                                  1.0 / static_cast<double>(counts.size()));
    bool shrunk = false;
    for (int& c : counts) {
      const int n =
          std::max(fewest, static_cast<int>(std::floor((c - 1) * ratio)) + 1);  // ratio < 1: n < c unless fewest
      shrunk = shrunk || n < c;
      c = n;
    }
    if (!shrunk) break;  // every axis at its minimum; check_error_target refused caps below it
  }
  return counts;
}

}  // namespace

double min_max_error(Encoding encoding) noexcept {
  switch (encoding) {
    case Encoding::half: return std::ldexp(1.0, -10);
    case Encoding::unorm16: return 1.0 / Unorm16::kMaxCode;  // 2 x 1/131070, the rounding of a range-1 table
    case Encoding::single: break;
  }
  return std::ldexp(1.0, -23);
}

void check_error_target(double max_error, std::uint64_t max_bytes, Law law, Encoding encoding) {
  const Named target{"max_error", format_number(max_error)};
  if (!std::isfinite(max_error) || !(max_error > 0.0))
    throw InputError({target, " is not allowed; expected a positive number"});
  if (max_error < min_max_error(encoding)) {
    std::vector<InputError::Piece> message{
        target, " is below what a " + std::string(to_string(encoding)) +
                    " table can hold (its rounding alone); allowed: >= " + format_number(min_max_error(encoding))};
    if (encoding != Encoding::single)
      message.insert(message.end(), {" (use ", Named{"encoding", "float"}, " for less)"});
    throw InputError(message);
  }
  const std::uint64_t smallest = bytes_of(std::vector<int>(law == Law::g ? 3 : 1, 4), encoding);
  if (max_bytes != 0 && max_bytes < smallest)
    throw InputError({Named{"max_bytes", std::to_string(max_bytes)},
                      " is too small; the smallest " + std::string(to_string(encoding)) + " table of law " +
                          to_string(law) + " needs " + std::to_string(smallest) + " value bytes"});
}

void check_fetch_budget(long long fetches) {
  if (fetches < 1)
    throw InputError({Named{"fetches", std::to_string(fetches)},
                      " is not allowed; expected an integer >= 1 (texture fetches per lookup)"});
}

InputError needs_target(const std::string& parameter) {
  const std::string why = parameter == "max_bytes" ? "it caps the value bytes of that search's tables"
                          : parameter == "fetches" ? "it is the fetch budget of that search"
                                                   : "it is what that search keeps when it misses";
  return InputError({Named{parameter}, " needs ", Named{"max_error"}, " (" + why + ")"});
}

namespace {

/// What one search found: the table that met E, or the best error it measured, that table's size
/// and, for a best-effort bake, the table.
struct SearchResult {
  std::optional<Table> table;
  std::optional<Table> best_table;
  double best_error = std::numeric_limits<double>::infinity();
  double best_bytes = 0.0;
  int best_fetches = 0;
};

/// The tables one fetch-budgeted bake_to_error has baked, by what decides their contents (the other
/// options are the same for all of its searches): a later search asking for one of them, or for the
/// texelFetch twin of a hardware-filtered linear one (bake_resolution), takes it instead of baking it
/// again. Bakes are deterministic, so the search's outcome is the same; kept up to kMaxBytes in memory.
class BakedTables {
 public:
  const Table* find(const BakeOptions& options) const {
    for (const Table& t : tables_)
      if (t.filter == options.filter && t.interpolation == options.interpolation &&
          (t.frame == Frame::warped) == options.warped && axis_counts(t.axes) == options.resolution)
        return &t;
    return nullptr;
  }
  void add(Table table) {
    const std::uint64_t bytes = table.entries() * (sizeof(float) * 2);  // values and errors
    if (bytes_ + bytes > kMaxBytes) return;
    bytes_ += bytes;
    tables_.push_back(std::move(table));
  }

 private:
  static constexpr std::uint64_t kMaxBytes = std::uint64_t{64} << 20;
  std::vector<Table> tables_;
  std::uint64_t bytes_ = 0;
};

/// The count search of the file comment for one scheme (frame, filter, starting interpolation set
/// in `options`); Catmull–Rom searches may switch to linear when it predicts fewer bytes. With
/// `best_effort`, the most accurate table baked is kept for when none meets E. `baked_tables`, when
/// given, is shared by the searches of one bake_to_error.
SearchResult search_counts(const Model& model, Law law, BakeOptions options, double E, std::uint64_t cap,
                           bool best_effort, BakedTables* baked_tables) {
  const double dims = static_cast<double>(options.resolution.size());
  // Each axis' share of E: the validated error is kLookupMargin x the measured one, and the
  // axes' errors may add at one point.
  const double share = E / (kLookupMargin * dims) * 0.8;
  const bool may_switch = options.interpolation == Interpolation::catmull_rom;
  SearchResult result;
  std::vector<std::pair<std::vector<int>, Interpolation>> baked;
  double previous_error = 0.0, previous_growth = 0.0;  // the last linear-only step: its error and growth
  double previous_spline_error = 0.0;                  // and the last b-spline table's error and bytes
  std::uint64_t previous_spline_bytes = 0;
  for (int attempt = 0; attempt < kMaxSearchBakes; ++attempt) {
    // Far over the cap, the capped table would miss E by far and could take hours to bake (at
    // the default cap, 64 MiB of hvd-empirical's g): refuse with what was measured instead.
    if (static_cast<double>(bytes_of(options.resolution, options.encoding)) > kCapFitReach * static_cast<double>(cap))
      break;
    options.resolution =
        fit_to_cap(options.resolution, options.encoding, cap, std::max(4, min_count(options.interpolation)));
    const std::pair<std::vector<int>, Interpolation> key{options.resolution, options.interpolation};
    if (std::find(baked.begin(), baked.end(), key) != baked.end()) break;  // capped to a table already measured
    baked.push_back(key);
    Table table;
    if (const Table* earlier = baked_tables ? baked_tables->find(options) : nullptr) {
      throw_if_cancelled(options);
      table = *earlier;
    } else {
      const bool twinned = baked_tables && options.filter == Filter::hardware &&
                           options.interpolation == Interpolation::linear;  // the texelFetch scheme's grid
      Table twin;
      table = bake_resolution(model, law, options, twinned ? &twin : nullptr);
      if (baked_tables) baked_tables->add(table);
      if (twinned) baked_tables->add(std::move(twin));
    }
    // The warp has one sample per theta_j node (tables/frame.h): refitted when that count changes.
    if (table.frame == Frame::warped) options.warp = table.warp;
    if (table.lookup_error <= E) {
      result.table = std::move(table);
      return result;
    }
    if (table.lookup_error < result.best_error) {
      result.best_error = table.lookup_error;
      result.best_bytes = static_cast<double>(value_bytes(table));
      result.best_fetches = fetches(table);
      if (best_effort) result.best_table = table;
    }
    // Calibrate the per-axis estimates of each interpolation with the validated error (the
    // estimates see node differences only; the validation sees the whole domain).
    const bool spline = options.interpolation == Interpolation::bspline;
    const Interpolation cubic_kind = spline ? Interpolation::bspline : Interpolation::catmull_rom;
    const std::vector<double> cubic = axis_error_estimates(table, cubic_kind);
    double sum = 0.0;
    for (double e : cubic) sum += e;
    const double measured = table.interpolation_error;
    const double calibration = sum > 0.0 ? std::max(1.0, measured / sum) : 1.0;
    std::vector<int> next = counts_for(options.resolution, cubic, calibration, share, cubic_kind);
    Interpolation next_interpolation = may_switch || spline ? cubic_kind : Interpolation::linear;
    if (spline) {
      // A larger b-spline table that did not lower the error is not converging towards E (a
      // feature no node count resolves, as for linear below): a still larger one is not worth its
      // bake. (A smaller one, reshaped by the estimates or the cap, may err more and go on.)
      const std::uint64_t bytes = value_bytes(table);
      if (previous_spline_bytes > 0 && bytes > previous_spline_bytes && table.lookup_error >= previous_spline_error)
        break;
      previous_spline_error = table.lookup_error;
      previous_spline_bytes = bytes;
      if (options.filter == Filter::hardware) {
        // The 8-bit weights fall only as h (a b-spline's two linear fetches per axis move by at most
        // the coefficients' step / 256): every axis grows by up to what they need. The reach adds
        // every axis' largest step, a worst case the b-spline's validated errors stay well below,
        // so unlike linear's it does not end the search.
        const double needed = weight_rounding_reach(table) * kLookupMargin / (kLinearAim * E);
        for (std::size_t d = 0; d < next.size(); ++d)
          next[d] = std::max(
              next[d],
              static_cast<int>(std::ceil((options.resolution[d] - 1) * std::min(needed, kLinearMaxGrowth))) + 1);
      }
    } else if (!may_switch) {
      // A linear-only scheme keeps its starting shape (chosen for it) and grows every axis by the
      // factor that brings the validated error to kLinearAim x E (error ~ h^2): the per-axis
      // estimates, maxima of second differences, overshot the warped frame's tables by ~10x in bytes.
      // When the last growth by r cut the error by less than r (slower than first order: a feature
      // no node count resolves, such as ggx's grazing band), a larger table is not worth its bake.
      if (previous_growth > 0.0 && previous_error / table.lookup_error < previous_growth) break;
      double ratio = std::clamp(std::sqrt(table.lookup_error / (kLinearAim * E)), 1.1, kLinearMaxGrowth);
      if (options.filter == Filter::hardware) {
        // The 8-bit weights alone must fit under E / kLookupMargin: every axis grows by at least
        // `needed`; a table that would pass the cap for that alone is out of reach of this scheme.
        const double needed = weight_rounding_reach(table) * kLookupMargin / (kLinearAim * E);
        if (needed > 1.0 && static_cast<double>(value_bytes(table)) * std::pow(needed, dims) > static_cast<double>(cap))
          break;
        ratio = std::max(ratio, std::min(needed, kLinearMaxGrowth));
      }
      previous_error = table.lookup_error;
      previous_growth = ratio;
      for (std::size_t d = 0; d < next.size(); ++d)
        next[d] = static_cast<int>(std::ceil((options.resolution[d] - 1) * ratio)) + 1;
    } else if (options.interpolation == Interpolation::catmull_rom) {  // would linear be smaller?
      const std::vector<double> linear = axis_error_estimates(table, Interpolation::linear);
      std::vector<int> lin = counts_for(options.resolution, linear, 1.0, share, Interpolation::linear);
      for (int& c : lin) c = std::max(c, 2);
      if (bytes_of(lin, options.encoding) < bytes_of(next, options.encoding)) {
        next = lin;
        next_interpolation = Interpolation::linear;
      }
    }
    if (next_interpolation == options.interpolation) {
      // Never repeat a failed bake: grow by at least the ratio of the errors.
      const double grow = std::pow(table.lookup_error / E, 1.0 / order(next_interpolation)) * 1.05;
      bool larger = false;
      for (std::size_t d = 0; d < next.size(); ++d) larger = larger || next[d] > options.resolution[d];
      if (!larger)
        for (std::size_t d = 0; d < next.size(); ++d)
          next[d] = static_cast<int>(std::ceil((options.resolution[d] - 1) * grow)) + 1;
    }
    options.resolution = next;
    options.interpolation = next_interpolation;
  }
  return result;
}

/// One scheme a fetch-budgeted search tries: frame (warped needs a lobe frame), lookup, filter.
struct Scheme {
  bool warped = false;
  Interpolation interpolation = Interpolation::linear;
  Filter filter = Filter::texel_fetch;
};

}  // namespace

Table bake_to_error(const Model& model, Law law, const TargetBake& requested) {
  const ErrorTarget& target = requested.target;
  const double E = target.lookup_error;
  check_error_target(E, target.max_bytes, law, requested.encoding);
  if (target.max_fetches != 0) check_fetch_budget(target.max_fetches);
  const std::uint64_t cap = target.max_bytes ? target.max_bytes : kDefaultMaxValueBytes;
  BakeOptions options;  // every grid choice is the search's; encoding, budget and progress are the caller's
  static_cast<BakeCommon&>(options) = requested;
  options.tolerance = E / kNodeToleranceRatio;
  options.check_tolerance = E / kCheckToleranceRatio;
  options.random_checks = kSearchChecks;
  options.lobe = law == Law::g ? lobe_frame_of(model) : std::nullopt;
  options.resolution = initial_counts(law);
  auto finish = [&](Table table) {
    table.target_error = E;
    table.target_bytes = cap;
    table.target_fetches = target.max_fetches;
    return table;
  };
  if (target.max_fetches == 0) {  // no budget: the fewest bytes, read with texelFetch
    options.interpolation = Interpolation::catmull_rom;
    SearchResult found = search_counts(model, law, options, E, cap, target.best_effort, nullptr);
    if (found.table) return finish(std::move(*found.table));
    if (found.best_table) return finish(std::move(*found.best_table));
    // Only what was measured: the refusal names the best table a bake made, never an extrapolation
    // to the cap (a number no bake has checked).
    throw InputError({std::string("cannot reach "), Named{"max_error", format_number(E)},
                      " for law " + std::string(to_string(law)) + " of '" + model.spec() + "' within " +
                          std::to_string(cap) + " value bytes (",
                      target.max_bytes ? InputError::Piece(Named{"max_bytes"}) : "the default cap",
                      "); the best this search found is " + format_number(found.best_error) + " in " +
                          format_number(found.best_bytes) + " value bytes (the search bakes at most " +
                          std::to_string(kMaxSearchBakes) + " tables)"});
  }
  const std::size_t D = law == Law::g ? 3 : 1;
  // In the order of their fetches (g): 1 hardware-filtered, 8 texel fetches of the same linear blend in
  // full precision (no 8-bit weights to absorb: the warped frame reaches 1e-4 in fewer bytes than
  // Catmull–Rom's lobe frame), 8 hardware-filtered of the b-spline (2 per axis), 64 of Catmull–Rom.
  const std::vector<Scheme> all{{options.lobe.has_value(), Interpolation::linear, Filter::hardware},
                                {options.lobe.has_value(), Interpolation::linear, Filter::texel_fetch},
                                {options.lobe.has_value(), Interpolation::bspline, Filter::hardware},
                                {false, Interpolation::catmull_rom, Filter::texel_fetch}};
  std::vector<Scheme> schemes;
  for (const Scheme& scheme : all)
    if (fetches(scheme.interpolation, scheme.filter, D) <= target.max_fetches) schemes.push_back(scheme);
  // The first scheme (fewest fetches) that meets E within the cap wins; when several fit the budget,
  // a first pass holds each to kCompactValueBytes, so that a few more fetches of a small table win
  // over one fetch of a table many times its size (a cache-unfriendly texture and a long bake).
  std::vector<std::uint64_t> caps{cap};
  if (schemes.size() > 1 && cap > kCompactValueBytes) caps.insert(caps.begin(), kCompactValueBytes);
  SearchResult best;
  BakedTables baked_tables;
  for (std::uint64_t pass_cap : caps)
    for (const Scheme& scheme : schemes) {
      BakeOptions o = options;
      o.warped = scheme.warped;
      o.interpolation = scheme.interpolation;
      o.filter = scheme.filter;
      if (scheme.warped) o.resolution = {13, 25, 9};  // the offset axis needs the most nodes (docs/tradeoff.md)
      SearchResult found = search_counts(model, law, o, E, pass_cap, target.best_effort, &baked_tables);
      if (found.table) return finish(std::move(*found.table));
      if (found.best_error < best.best_error) best = std::move(found);
    }
  if (best.best_table) return finish(std::move(*best.best_table));
  throw InputError({std::string("cannot reach "), Named{"max_error", format_number(E)},
                    " for law " + std::string(to_string(law)) + " of '" + model.spec() + "' within " +
                        std::to_string(target.max_fetches) + " texture fetch" + (target.max_fetches == 1 ? "" : "es") +
                        " per lookup (",
                    Named{"fetches"}, ") and within " + std::to_string(cap) + " value bytes (",
                    target.max_bytes ? InputError::Piece(Named{"max_bytes"}) : "the default cap",
                    "); the best found is " + format_number(best.best_error) + " at " +
                        std::to_string(best.best_fetches) + " fetch" + (best.best_fetches == 1 ? "" : "es") + " in " +
                        format_number(best.best_bytes) + " value bytes"});
}

}  // namespace ganzfeld::tables
