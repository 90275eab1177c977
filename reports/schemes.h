// The table schemes side by side (`ganzfeld tradeoff --schemes`): for one model and
// law, format version 1's scheme (cosines frame, linear lookup) against version 2's (lobe frame,
// Catmull–Rom) and what `bake --max-error` picks (float, and for g `--encoding unorm16`: issue
// the 16-bit target), linear vs cubic and half vs float at that pick,
// and for g the plain trilinear lookup (one hardware-filtered fetch) in the lobe frame, each
// measured for error, value bytes and bake time.
//
// The reference is direct cubature at kSchemeReferenceTolerance at `points` seeded random points
// (reports/tradeoff.h reference_directions without the extremes, j·n in [kSchemeMinCos, 1]):
// points no table is built from (the tables validate themselves at other seeds and at cell
// centres). Its engine, integrate/, is held to an independent quadrature (Boost.Math
// Gauss–Kronrod) by tests/independent_reference_test.cpp. Bake times are the median and the
// spread (min–max) of `repeats` runs (util/timing.h).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "models/model.h"
#include "reports/tradeoff.h"
#include "tables/table.h"

namespace ganzfeld::reports {

/// The measurement of docs/tradeoff.md, part 1: >= 2000 points, j·n in [0.02, 1], cubature at 1e-10.
inline constexpr double kSchemeMinCos = 0.02;
inline constexpr double kSchemeReferenceTolerance = 1e-10;
/// Cubature tolerance of the fixed-resolution rows: far below their interpolation errors.
inline constexpr double kSchemeTolerance = 1e-6;
/// The trilinear rows' target (<= 1e-3 with one hardware-filtered fetch); the smallest
/// float row within it is measured in half floats too.
inline constexpr double kTrilinearTarget = 1e-3;
/// The target within 8 fetches per law: 1e-4 in 256 kB (bake --max-error 1e-4 --max-bytes 256000
/// --fetches 8).
inline constexpr double kEightFetchTarget = 1e-4;
inline constexpr std::uint64_t kEightFetchBytes = 256000;

/// The families of rows, in the order they are measured and listed.
enum class SchemeKind {
  today,        ///< version 1: cosines frame, default mappings, linear (at fixed resolutions)
  max_error,    ///< bake --max-error E: the frame, interpolation and resolution it picks
  swapped,      ///< the 1e-4 pick with the other interpolation (linear <-> Catmull–Rom)
  half,         ///< the 1e-4 pick in half floats
  trilinear,    ///< g: lobe frame (cosines when the model has none), linear, fixed resolutions; and
                ///< the smallest within kTrilinearTarget in half floats
  one_fetch,    ///< g: warped frame (cosines when the model has no lobe), linear, hardware filter, at
                ///< fixed resolutions, the finest again read with texelFetch (2^D fetches, full-precision
                ///< weights), the smallest within kTrilinearTarget again in unorm16; and bake
                ///< --max-error 1e-3 --fetches 1 and --max-error 1e-4 --max-bytes 256000 --fetches 8.
                ///< Hardware-filtered rows' errors are the worst of the full-precision and both 8-bit
                ///< filter lookups.
  eight_fetch,  ///< g, with one_fetch: the same frame with the b-spline read as 2 hardware-filtered
                ///< fetches per axis (8), at fixed resolutions (errors as for one_fetch)
};
const char* to_string(SchemeKind kind);

struct SchemeRow {
  SchemeKind kind = SchemeKind::today;
  double target = 0.0;  ///< max_error rows: E (and target_bytes, 0: the default cap)
  std::uint64_t target_bytes = 0;
  std::string refused;  ///< max_error rows the baker refused: its message (no table)
  tables::Frame frame = tables::Frame::cosines;
  tables::Interpolation interpolation = tables::Interpolation::linear;
  tables::Encoding encoding = tables::Encoding::single;
  std::vector<int> resolution;
  std::uint64_t value_bytes = 0;     ///< what a shader uploads (tables::value_bytes)
  std::vector<double> bake_seconds;  ///< wall time of each run
  double max_error = 0.0;            ///< max |lookup - reference| over the reference points
  double rms_error = 0.0;
  double lookup_error = 0.0;  ///< the table's stated bound (Table::lookup_error)
  double covered = 0.0;       ///< fraction of the points where |lookup - reference| <= lookup_error
  int fetches = 0;            ///< texture fetches per lookup (tables::fetches)
  tables::Filter filter = tables::Filter::texel_fetch;
  int target_fetches = 0;  ///< max_error rows: --fetches (0: none)
};

struct SchemeOptions {
  int points = 2000;
  std::uint64_t seed = 1;
  int repeats = 3;              ///< bake runs per row (median and spread)
  bool quick = false;           ///< fewer rows (tests): coarser resolutions, E = 1e-3 only
  bool one_fetch_only = false;  ///< only the one_fetch family (models whose other searches take too long)
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct SchemeReport {
  std::string model;
  Law law = Law::g;
  Reference reference;
  std::vector<SchemeRow> rows;
  int repeats = 1;
  double seconds = 0.0;
};

/// Runs the measurement; throws InputError for a law without tables, an anisotropic model, points < 1
/// or repeats < 1. A --max-error row the baker refuses is kept with its message.
SchemeReport measure_schemes(const Model& model, Law law, const SchemeOptions& options);

/// Median, min and max of a row's bake times.
struct Spread {
  double median = 0.0, min = 0.0, max = 0.0;
};
Spread bake_spread(const SchemeRow& row);

/// A row's short description: "today 33x33x17", "max-error 1e-4", ...
std::string scheme_label(const SchemeRow& row);

/// The report as Markdown: the command, the reference, then one table row per scheme.
std::string schemes_markdown(const SchemeReport& report, const std::string& command, const std::string& plot);

/// Two log-log panels, max error vs value bytes and vs median bake time, a colour per kind.
void write_schemes_plot(const SchemeReport& report, const std::string& path);

}  // namespace ganzfeld::reports
