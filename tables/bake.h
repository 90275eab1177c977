// Baking: every node of a law's table computed by cubature (integrate/laws.h), in parallel,
// deterministically (each entry is an independent integral, so the bits do not depend on the
// thread count or the order of work).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "integrate/cubature.h"
#include "models/model.h"
#include "tables/frame.h"
#include "tables/table.h"

namespace ganzfeld::tables {

/// Tables larger than this are refused before anything is allocated (value + error, 4 bytes
/// each, as held in memory).
inline constexpr std::uint64_t kMaxTableBytes = std::uint64_t{2} << 30;  // 2 GiB
inline constexpr std::uint64_t kBytesPerEntry = 2 * sizeof(float);

/// What every bake takes, whichever kind it is: how the values are stored and each entry's
/// evaluation budget.
struct BakeCommon {
  long long max_evaluations = CubatureOptions{}.max_evaluations;  ///< per entry
  Encoding encoding = Encoding::single;
  /// Called with (entries done, total) at most ~kProgressSteps times, serialized (never two at
  /// once) and with increasing `done`, from whichever worker thread finished the entry.
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;
  /// When set, read before every entry and by every entry's cubature (CubatureOptions::cancel):
  /// once it holds true the bake stops and throws Cancelled (no table, nothing written).
  const std::atomic<bool>* cancel = nullptr;
};

/// A bake on a fixed grid: the caller chooses every node count, axis, lookup and tolerance.
struct BakeOptions : BakeCommon {
  std::vector<int> resolution;  ///< nodes per axis (g: 3 counts; h, a: 1)
  /// Mapping per axis (same count as `resolution`); empty = the law's defaults (default_axes).
  std::vector<Mapping> mappings;
  double tolerance = 1e-9;  ///< absolute tolerance of every entry's cubature
  Interpolation interpolation = Interpolation::linear;
  /// g only: bake in the lobe frame with this peak and width (tables/frame.h); nothing: the
  /// cosines frame (version 1's axes; `mappings` apply).
  std::optional<LobeFrame> lobe;
  /// With `lobe`: the warped frame instead of the lobe frame (tables/frame.h), with this warp, or
  /// one fitted to the model (fit_warp) when nothing is given or its sample count is not the
  /// number of theta_j nodes.
  bool warped = false;
  std::optional<Warp> warp;
  /// The lookup the bound covers and the exported shader performs: hardware filtering makes the
  /// validation take the worst of exact, nearest-rounded and truncated 8-bit weights.
  Filter filter = Filter::texel_fetch;
  /// Validation after baking: seeded random points uniform in the law's coordinates (g: i·n in
  /// [-1, 1], j·n in [0, 1], phi in [0, pi]; h, a: [0, 1]) in addition to the cell centres.
  std::uint64_t random_checks = 0;
  /// Tolerance of the direct cubature the validation compares with (0: `tolerance`).
  double check_tolerance = 0.0;
};

/// What a bake to an error must meet (tables/to_error.h).
struct ErrorTarget {
  double lookup_error = 0.0;    ///< E > 0: the validated lookup error to reach
  std::uint64_t max_bytes = 0;  ///< cap of the value bytes (0: kDefaultMaxValueBytes)
  /// The most texture fetches one lookup may cost a shader (tables::fetches; 0: no budget, the
  /// fewest value bytes the search finds among texel-fetch lookups).
  int max_fetches = 0;
  /// When no scheme within the budget reaches lookup_error, keep the most accurate table the
  /// search baked (its stated lookup error says by how much it misses) instead of refusing.
  /// What the scene defaults ask for; an explicit --max-error is strict.
  bool best_effort = false;
};

/// A bake to an error target: the baker chooses resolution, mappings, frame, interpolation,
/// filter and tolerance (tables/to_error.h), so none of them can be given.
struct TargetBake : BakeCommon {
  ErrorTarget target;
};

/// What to bake: a fixed grid or an error target. The kinds share only BakeCommon, so no field
/// means one thing in one kind and is silently replaced in the other.
using BakeRequest = std::variant<BakeOptions, TargetBake>;

/// The fields both kinds share.
BakeCommon& common(BakeRequest& request) noexcept;
const BakeCommon& common(const BakeRequest& request) noexcept;

inline constexpr int kProgressSteps = 1000;
/// The interpolation check after baking (Table::interpolation_error): at least this many cell
/// centres (all cells when there are fewer), with a fixed seed so bakes are reproducible.
inline constexpr std::uint64_t kMinInterpolationChecks = 512;
inline constexpr std::uint64_t kInterpolationSeed = 20190117;
/// Seed of the random validation points (BakeOptions::random_checks).
inline constexpr std::uint64_t kValidationSeed = 20240615;

/// The stored number nearest to x in the encoding.
float round_to_encoding(double x, Encoding encoding) noexcept;
/// The smallest stored number >= x >= 0 in the encoding (error bounds may only round up).
float round_up_to_encoding(double x, Encoding encoding) noexcept;

/// Parses "N", "NxN" or "NxNxN" into node counts; a single N stands for every axis of the law
/// (g: N x N x N). Throws InputError naming the text and the expected form.
std::vector<int> parse_resolution(const std::string& text, Law law);

/// "64x64x32": node counts joined by x.
std::string resolution_text(const std::vector<int>& resolution);

/// Memory the table would need, in bytes (entries x kBytesPerEntry), saturating at UINT64_MAX.
std::uint64_t table_bytes(const std::vector<int>& resolution) noexcept;

/// What a shader uploads: the value channel only, entries x (4 bytes float, 2 bytes half).
std::uint64_t value_bytes(const Table& table) noexcept;

/// The axes bake(model, law, options) uses: lobe_axes when options.lobe (g), else make_axes.
std::vector<Axis> bake_axes(Law law, const BakeOptions& options);

/// Bakes law g, h or a of an isotropic model (axes: make_axes(law, resolution, mappings): the
/// default mappings unless overridden). Refuses (InputError) other
/// laws, anisotropic models, counts < 2 and tables above kMaxTableBytes before allocating, and
/// values outside the half range when encoding = half. Entries that miss the tolerance are
/// kept with their (larger) error estimate and counted in Table::unconverged.
/// Table::command is left empty for the caller; Table::version is this build's.
/// `texel_fetch_twin`, when given for a hardware-filtered bake: the same table read with texelFetch
/// (the full-precision lookup alone validated at the same points), identical to bake_resolution
/// with filter texel_fetch, for the price of one bake.
Table bake_resolution(const Model& model, Law law, const BakeOptions& options, Table* texel_fetch_twin = nullptr);

/// Throws Cancelled once options.cancel holds true: a bake whose flag was set while it ran is thrown
/// away (some entries were skipped or cut short), and a search returns no table.
void throw_if_cancelled(const BakeCommon& options);

/// The table `request` asks for: bake_resolution of a fixed grid, bake_to_error
/// (tables/to_error.h) of an error target. Throws Cancelled once BakeCommon::cancel holds true.
Table bake(const Model& model, Law law, const BakeRequest& request);

/// `count` seeded random points uniform in the law's coordinates, flattened (g: (i·n in
/// [-1, 1], j·n in [min_cos_j, 1], phi in [0, pi]) each; h, a: cos theta in [0, 1]). Prefix-stable.
std::vector<double> validation_points(Law law, std::uint64_t count, std::uint64_t seed = kValidationSeed,
                                      double min_cos_j = 0.0);

}  // namespace ganzfeld::tables
