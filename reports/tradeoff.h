// The speed/accuracy trade of a table, measured (`ganzfeld tradeoff`).
//
// What is measured, in one run, for one model and one law (g, h or a):
//  1. A reference: a fixed list of directions — extreme points first (grazing, i·n = -1, ±n,
//     φ = 0 and π), then N seeded random points uniform in the law's coordinates (g: i·n in
//     [-1, 1], j·n in [0, 1], φ in [0, π]; h, a: cos θ in [0, 1]) — each evaluated by cubature
//     (integrate/laws.h) at a tolerance far below any table's (kReferenceTolerance).
//  2. For every configuration (resolution × mappings × encoding × cubature tolerance): bake the
//     table (wall time), count its bytes (in memory and as the EXR file actually written), time
//     lookups (single thread, many lookups), and compare the lookup at every reference
//     direction with the reference: max and RMS |lookup − reference|. The lookup is exactly
//     what `ganzfeld sample` does (tables::sample on directions).
// The point list is prefix-stable: the points for N are the first points for any N' > N with
// the same seed, so a measurement with fewer points never reports a larger max error.
// max_error is an empirical maximum over the reference points, not a bound: between them the
// interpolation error can be somewhat larger (tests/tradeoff_test.cpp measures by how much on
// fresh points).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "models/model.h"
#include "tables/table.h"

namespace ganzfeld::reports {

/// Tolerance of the reference cubature: two decades below the tightest table tolerance swept
/// (1e-9), so that the reference's own error never shows in the measured lookup errors.
inline constexpr double kReferenceTolerance = 1e-11;

struct TradeoffConfig {
  std::vector<int> resolution;            ///< nodes per axis
  std::vector<tables::Mapping> mappings;  ///< one per axis (resolved: never empty)
  tables::Encoding encoding = tables::Encoding::single;
  double tolerance = 1e-9;  ///< cubature tolerance of the bake
};

/// The sweep: every combination of the lists, in the order mapping set → encoding → tolerance →
/// resolution (so that consecutive rows are one series with growing resolution).
struct TradeoffPlan {
  std::vector<std::vector<int>> resolutions;
  std::vector<std::vector<tables::Mapping>> mapping_sets;  ///< each one mapping per axis
  std::vector<tables::Encoding> encodings;
  std::vector<double> tolerances;
  std::vector<TradeoffConfig> configurations() const;
};

/// The documented sweep (a full run of one model in well under two minutes on two cores):
///   g: 9x9x5, 17x17x9, 33x33x17, 65x65x33; h, a: 9, 17, 33, 65, 129, 257 nodes;
///   mappings: the law's defaults and all-linear; encodings half and float;
///   tolerances 1e-4, 1e-6, 1e-9.
TradeoffPlan full_plan(Law law);
/// A few configurations for tests and CI (seconds): the three coarsest g resolutions (h, a: 9,
/// 33, 129), both mapping sets and encodings, tolerances 1e-4 and 1e-9.
TradeoffPlan quick_plan(Law law);

/// The reference directions: extremes first, then `random_points` seeded random ones.
struct Direction {
  Vec3 i, j;
};
/// With extremes = false only the random ones; min_cos (< 1) lower-bounds the random j·n of g and
/// the cosine of h and a (the targets' range: j·n in [0.02, 1]).
std::vector<Direction> reference_directions(Law law, int random_points, std::uint64_t seed, bool extremes = true,
                                            double min_cos = 0.0);

/// Directions i, j of law coordinates x (g: i·n, j·n, φ; h: j·n; a: i·n), as the baker places
/// them (docs/lut-format.md).
Direction direction_of(Law law, std::span<const double> x);

struct ReferencePoint {
  Direction direction;
  double value = 0.0;
  double error = 0.0;  ///< the cubature's error estimate
  bool converged = true;
};

struct Reference {
  std::vector<ReferencePoint> points;
  int extreme_points = 0;  ///< how many of `points` (the first ones) are extremes
  std::uint64_t seed = 0;
  double tolerance = kReferenceTolerance;
  double max_error = 0.0;  ///< largest error estimate of any reference value
  long long unconverged = 0;
  double seconds = 0.0;  ///< wall time of the reference cubature
};

/// Evaluates the law at reference_directions(law, random_points, seed) (in parallel,
/// deterministically).
Reference compute_reference(const Model& model, Law law, int random_points, std::uint64_t seed,
                            double tolerance = kReferenceTolerance, bool extremes = true, double min_cos = 0.0);

/// Max and RMS |lookup − reference| of a table over the reference points, and where the max is.
struct LookupError {
  double max = 0.0;
  double rms = 0.0;
  std::size_t worst = 0;  ///< index into Reference::points
};
LookupError lookup_error(const tables::Table& table, const Reference& reference);

struct TradeoffRow {
  TradeoffConfig config;
  std::uint64_t entries = 0;
  std::uint64_t bytes = 0;          ///< in memory: entries × 2 channels (value, error) × 2 or 4 bytes
  std::uint64_t texture_bytes = 0;  ///< the value channel alone (what a shader uploads)
  std::uint64_t file_bytes = 0;     ///< size of the EXR file written (ZIP-compressed)
  double bake_seconds = 0.0;        ///< wall time of tables::bake (parallel)
  double lookup_ns = 0.0;           ///< per tables::sample on axis coordinates, one thread
  double max_error = 0.0;           ///< max |lookup − reference| over the reference points
  double rms_error = 0.0;
  double max_stored_error = 0.0;  ///< Table::max_error (cubature + rounding at the nodes)
  long long unconverged = 0;      ///< entries whose cubature missed the tolerance
  Direction worst;                ///< where max_error was reached
};

struct TradeoffOptions {
  int points = 2000;  ///< random reference points (extremes come on top)
  std::uint64_t seed = 1;
  double reference_tolerance = kReferenceTolerance;
  /// Called after each configuration with (rows done, rows total).
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct TradeoffReport {
  std::string model;  ///< canonical spec
  Law law = Law::g;
  Reference reference;
  std::vector<TradeoffRow> rows;
  double seconds = 0.0;  ///< wall time of the whole measurement
};

/// Runs the measurement. Throws InputError for a law other than g, h, a, an anisotropic model or
/// points < 1; the EXR files go to a private temporary directory that is removed afterwards.
TradeoffReport measure_tradeoff(const Model& model, Law law, const TradeoffPlan& plan, const TradeoffOptions& options);

/// "65x65x33", "cos,cos,linear".
std::string mappings_text(const std::vector<tables::Mapping>& mappings);

/// The report as Markdown: a summary computed from the rows (between the lines
/// "<!-- summary -->" and "<!-- /summary -->"), then the table of rows. `command` is the command
/// line that produced it; `plot` (may be empty) the PNG to link.
std::string tradeoff_markdown(const TradeoffReport& report, const std::string& command, const std::string& plot);

/// The plot: two log-log panels, max error vs bytes and max error vs bake time, a colour per
/// mapping set × encoding and a marker per tolerance, decade ticks, legend. Written atomically
/// (temporary file beside `path`, then rename); InputError when it cannot be written, and then
/// nothing is left behind.
void write_tradeoff_plot(const TradeoffReport& report, const std::string& path);

}  // namespace ganzfeld::reports
