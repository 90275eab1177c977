#include "reports/tradeoff.h"

#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "reports/plot.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "tables/sample.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::reports {

using namespace ganzfeld::tables;

using std::numbers::pi;
namespace fs = std::filesystem;

// --- The sweep --------------------------------------------------------------------------------

std::vector<TradeoffConfig> TradeoffPlan::configurations() const {
  std::vector<TradeoffConfig> out;
  for (const auto& mappings : mapping_sets)
    for (Encoding encoding : encodings)
      for (double tolerance : tolerances)
        for (const auto& resolution : resolutions) out.push_back({resolution, mappings, encoding, tolerance});
  return out;
}

namespace {

std::vector<Mapping> default_mappings(Law law) {
  const std::vector<int> counts(law == Law::g ? 3 : 1, 2);
  std::vector<Mapping> m;
  for (const Axis& axis : default_axes(law, counts)) m.push_back(axis.mapping);
  return m;
}

std::vector<Mapping> linear_mappings(Law law) { return std::vector<Mapping>(law == Law::g ? 3 : 1, Mapping::linear); }

std::vector<std::vector<int>> one_d(std::initializer_list<int> counts) {
  std::vector<std::vector<int>> out;
  for (int c : counts) out.push_back({c});
  return out;
}

}  // namespace

TradeoffPlan full_plan(Law law) {
  require_tabulated(law);
  TradeoffPlan plan;
  plan.resolutions = law == Law::g ? std::vector<std::vector<int>>{{9, 9, 5}, {17, 17, 9}, {33, 33, 17}, {65, 65, 33}}
                                   : one_d({9, 17, 33, 65, 129, 257});
  plan.mapping_sets = {default_mappings(law), linear_mappings(law)};
  plan.encodings = {Encoding::half, Encoding::single};
  plan.tolerances = {1e-4, 1e-6, 1e-9};
  return plan;
}

TradeoffPlan quick_plan(Law law) {
  require_tabulated(law);
  TradeoffPlan plan;
  plan.resolutions =
      law == Law::g ? std::vector<std::vector<int>>{{9, 9, 5}, {17, 17, 9}, {33, 33, 17}} : one_d({9, 33, 129});
  plan.mapping_sets = {default_mappings(law), linear_mappings(law)};
  plan.encodings = {Encoding::half, Encoding::single};
  plan.tolerances = {1e-4, 1e-9};
  return plan;
}

// --- The reference ----------------------------------------------------------------------------

Direction direction_of(Law law, std::span<const double> x) {
  auto sin_of = [](double c) { return std::sqrt(std::max(0.0, 1.0 - c * c)); };
  if (law == Law::g) {
    const double ci = x[0], cj = x[1], phi = x[2];
    return {{sin_of(ci), 0.0, ci}, {sin_of(cj) * std::cos(phi), sin_of(cj) * std::sin(phi), cj}};
  }
  const Vec3 d{sin_of(x[0]), 0.0, x[0]};
  return law == Law::h ? Direction{{0, 0, 1}, d} : Direction{d, {0, 0, 1}};
}

std::vector<Direction> reference_directions(Law law, int random_points, std::uint64_t seed, bool extremes,
                                            double min_cos) {
  require_tabulated(law);
  std::vector<Direction> out;
  // Extremes: the ends of every axis and grazing angles just inside them.
  if (extremes && law == Law::g) {
    for (double ci : {-1.0, -0.5, 0.0, 0.999999, 1.0})
      for (double cj : {0.0, 1e-6, 1.0})
        for (double phi : {0.0, pi / 2, pi}) {
          const double x[3] = {ci, cj, phi};
          out.push_back(direction_of(law, x));
        }
  } else if (extremes) {
    for (double c : {0.0, 1e-8, 1e-4, 1e-2, 1.0}) {
      const double x[1] = {c};
      out.push_back(direction_of(law, x));
    }
  }
  // Random points, prefix-stable: point k depends only on the seed and k. The 64-bit Mersenne
  // Twister's output is fixed by the C++ standard; the conversion to [0, 1) is ours (53 bits),
  // so the points are the same with every standard library.
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  for (int k = 0; k < random_points; ++k) {
    if (law == Law::g) {
      const double ci = -1.0 + 2.0 * uniform();
      const double cj = min_cos + (1.0 - min_cos) * uniform();
      const double phi = pi * uniform();
      const double x[3] = {ci, cj, phi};
      out.push_back(direction_of(law, x));
    } else {
      const double x[1] = {min_cos + (1.0 - min_cos) * uniform()};
      out.push_back(direction_of(law, x));
    }
  }
  return out;
}

namespace {
int extreme_count(Law law) { return law == Law::g ? 45 : 5; }
}  // namespace

Reference compute_reference(const Model& model, Law law, int random_points, std::uint64_t seed, double tolerance,
                            bool extremes, double min_cos) {
  require_tabulated(law);
  if (random_points < 1)
    throw InputError({Named{"points", std::to_string(random_points)}, " is not allowed; expected an integer >= 1"});
  const util::Stopwatch start;
  Reference ref;
  ref.seed = seed;
  ref.tolerance = tolerance;
  ref.extreme_points = extremes ? extreme_count(law) : 0;
  const std::vector<Direction> dirs = reference_directions(law, random_points, seed, extremes, min_cos);
  ref.points.resize(dirs.size());
  CubatureOptions options;
  options.abs_tol = tolerance;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dirs.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) {
      const Estimate e = evaluate_law(model, law, dirs[p].i, dirs[p].j, options);
      ref.points[p] = {dirs[p], e.value, e.error, e.converged};
    }
  });
  for (const ReferencePoint& p : ref.points) {
    ref.max_error = std::max(ref.max_error, p.error);
    if (!p.converged) ++ref.unconverged;
  }
  ref.seconds = start.seconds();
  return ref;
}

LookupError lookup_error(const Table& table, const Reference& reference) {
  LookupError out;
  double sum_sq = 0.0;
  for (std::size_t p = 0; p < reference.points.size(); ++p) {
    const ReferencePoint& ref = reference.points[p];
    const double e = std::abs(sample(table, ref.direction.i, ref.direction.j).value - ref.value);
    sum_sq += e * e;
    if (e > out.max) {
      out.max = e;
      out.worst = p;
    }
  }
  if (!reference.points.empty()) out.rms = std::sqrt(sum_sq / static_cast<double>(reference.points.size()));
  return out;
}

// --- The measurement --------------------------------------------------------------------------

namespace {

// Lookup timing: at least this many lookups and this much time, so that the clock's resolution
// and the loop overhead are negligible (a lookup takes tens of ns).
constexpr std::uint64_t kMinLookups = 200'000;
constexpr double kMinLookupSeconds = 0.01;

volatile double g_lookup_sink = 0.0;  // keeps the timed lookups from being optimized away

double time_lookups(const Table& table, const std::vector<double>& coords) {
  const std::size_t dims = table.axes.size();
  const std::size_t n = dims ? coords.size() / dims : 0;
  if (n == 0) return 0.0;
  std::uint64_t lookups = 0;
  double sum = 0.0;
  const util::Stopwatch start;
  double elapsed = 0.0;
  do {
    for (std::size_t p = 0; p < n; ++p)
      sum += sample(table, std::span<const double>(coords.data() + p * dims, dims)).value;
    lookups += n;
    elapsed = start.seconds();
  } while (lookups < kMinLookups || elapsed < kMinLookupSeconds);
  g_lookup_sink = sum;
  return elapsed * 1e9 / static_cast<double>(lookups);
}

/// A private temporary directory, removed when it goes out of scope.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("ganzfeld-tradeoff-" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

}  // namespace

TradeoffReport measure_tradeoff(const Model& model, Law law, const TradeoffPlan& plan, const TradeoffOptions& options) {
  require_tabulated(law);
  if (!model.traits().isotropic)
    throw InputError("model '" + model.spec() + "' is anisotropic; tables exist only for isotropic models");
  const util::Stopwatch start;
  TradeoffReport report;
  report.model = model.spec();
  report.law = law;
  report.reference = compute_reference(model, law, options.points, options.seed, options.reference_tolerance);

  const std::vector<TradeoffConfig> configs = plan.configurations();
  TempDir temp;
  const fs::path exr = temp.path / "table.exr";
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const TradeoffConfig& config = configs[c];
    BakeOptions bake_options;
    bake_options.resolution = config.resolution;
    bake_options.mappings = config.mappings;
    bake_options.encoding = config.encoding;
    bake_options.tolerance = config.tolerance;
    const util::Stopwatch bake_start;
    Table table = bake(model, law, bake_options);
    TradeoffRow row;
    row.bake_seconds = bake_start.seconds();
    row.config = config;
    row.config.mappings.clear();
    for (const Axis& axis : table.axes) row.config.mappings.push_back(axis.mapping);
    row.entries = table.entries();
    const std::uint64_t bytes_per_number = config.encoding == Encoding::half ? 2 : 4;
    row.texture_bytes = row.entries * bytes_per_number;
    row.bytes = 2 * row.texture_bytes;
    table.command = "ganzfeld tradeoff (temporary table)";
    write_table(table, exr.string());
    row.file_bytes = fs::file_size(exr);
    fs::remove(exr);

    const LookupError error = lookup_error(table, report.reference);
    row.max_error = error.max;
    row.rms_error = error.rms;
    row.worst = report.reference.points.empty() ? Direction{} : report.reference.points[error.worst].direction;
    row.max_stored_error = table.node_error;
    row.unconverged = table.unconverged;

    std::vector<double> coords;
    for (const ReferencePoint& p : report.reference.points) {
      const std::vector<double> x = coordinates(law, p.direction.i, p.direction.j);
      coords.insert(coords.end(), x.begin(), x.end());
    }
    row.lookup_ns = time_lookups(table, coords);
    report.rows.push_back(std::move(row));
    if (options.progress) options.progress(c + 1, configs.size());
  }
  report.seconds = start.seconds();
  return report;
}

// --- Text -------------------------------------------------------------------------------------

std::string mappings_text(const std::vector<Mapping>& mappings) {
  std::string s;
  for (std::size_t d = 0; d < mappings.size(); ++d) {
    if (d) s += ',';
    s += to_string(mappings[d]);
  }
  return s;
}

namespace {

std::string fmt(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}
std::string sci(double x) { return fmt("%.2g", x); }

std::string bytes_text(std::uint64_t b) {
  if (b < 10'000) return std::to_string(b) + " B";
  if (b < 10'000'000) return fmt("%.0f kB", static_cast<double>(b) / 1e3);
  return fmt("%.1f MB", static_cast<double>(b) / 1e6);
}

std::string seconds_text(double s) { return s < 0.1 ? fmt("%.3f s", s) : s < 10 ? fmt("%.2f s", s) : fmt("%.1f s", s); }

bool same(const TradeoffConfig& c, const std::vector<Mapping>& mappings, Encoding encoding, double tolerance) {
  return c.mappings == mappings && c.encoding == encoding && c.tolerance == tolerance;
}

}  // namespace

std::string tradeoff_markdown(const TradeoffReport& report, const std::string& command, const std::string& plot) {
  std::ostringstream md;
  const auto& rows = report.rows;
  const Law law = report.law;
  const std::vector<Mapping> defaults = default_mappings(law);
  double tightest = std::numeric_limits<double>::infinity();
  std::vector<int> finest;
  auto product = [](const std::vector<int>& r) {
    std::uint64_t n = 1;
    for (int c : r) n *= static_cast<std::uint64_t>(c);
    return n;
  };
  for (const TradeoffRow& r : rows) {
    tightest = std::min(tightest, r.config.tolerance);
    if (finest.empty() || product(r.config.resolution) > product(finest)) finest = r.config.resolution;
  }
  auto find = [&](const std::vector<int>& res, const std::vector<Mapping>& m, Encoding e,
                  double tol) -> const TradeoffRow* {
    for (const TradeoffRow& r : rows)
      if (r.config.resolution == res && same(r.config, m, e, tol)) return &r;
    return nullptr;
  };

  md << "Measured by\n\n```sh\n" << command << "\n```\n\n";
  md << "Reference: " << report.reference.points.size() << " points (" << report.reference.extreme_points
     << " extremes + " << report.reference.points.size() - report.reference.extreme_points << " random, seed "
     << report.reference.seed << ") by cubature at tolerance " << sci(report.reference.tolerance)
     << " (largest error estimate " << sci(report.reference.max_error) << ", " << report.reference.unconverged
     << " unconverged), " << seconds_text(report.reference.seconds) << "; whole run " << seconds_text(report.seconds)
     << ".\n\n";

  md << "<!-- summary -->\n";
  md << "**" << report.model << ", law " << to_string(law) << "** (default mappings " << mappings_text(defaults)
     << ", float, tolerance " << sci(tightest) << "):\n";
  for (const TradeoffRow& r : rows)
    if (same(r.config, defaults, Encoding::single, tightest))
      md << "- " << resolution_text(r.config.resolution) << ": max error " << sci(r.max_error) << " (RMS "
         << sci(r.rms_error) << "), " << bytes_text(r.bytes) << " in memory, " << bytes_text(r.file_bytes)
         << " on disk, baked in " << seconds_text(r.bake_seconds) << ", " << fmt("%.0f", r.lookup_ns)
         << " ns per lookup.\n";
  const TradeoffRow* f = find(finest, defaults, Encoding::single, tightest);
  const TradeoffRow* h = find(finest, defaults, Encoding::half, tightest);
  const TradeoffRow* lin = find(finest, linear_mappings(law), Encoding::single, tightest);
  if (f && h)
    md << "- Half instead of float at " << resolution_text(finest) << ": max error " << sci(h->max_error) << " vs "
       << sci(f->max_error) << " (stored rounding up to " << sci(h->max_stored_error) << " vs "
       << sci(f->max_stored_error) << ") for half the bytes.\n";
  if (f && lin && f->max_error > 0)
    md << "- All-linear mappings instead of " << mappings_text(defaults) << " at " << resolution_text(finest)
       << ": max error " << sci(lin->max_error) << " vs " << sci(f->max_error) << " ("
       << fmt("%.2g", lin->max_error / f->max_error) << "x).\n";
  if (f) {
    md << "- Cubature tolerance at " << resolution_text(finest) << " (default mappings, float):";
    bool first = true;
    for (const TradeoffRow& r : rows)
      if (r.config.resolution == finest && same(r.config, defaults, Encoding::single, r.config.tolerance)) {
        md << (first ? " " : "; ") << sci(r.config.tolerance) << " → max error " << sci(r.max_error) << ", bake "
           << seconds_text(r.bake_seconds);
        first = false;
      }
    md << ".\n";
  }
  for (double target : {1e-2, 1e-3, 1e-4}) {
    const TradeoffRow* best = nullptr;
    for (const TradeoffRow& r : rows)
      if (r.max_error <= target && (!best || r.bytes < best->bytes ||  // ties: the smaller (deterministic) error
                                    (r.bytes == best->bytes && r.max_error < best->max_error)))
        best = &r;
    md << "- Smallest table with max error ≤ " << sci(target) << ": ";
    if (best)
      md << resolution_text(best->config.resolution) << " " << mappings_text(best->config.mappings) << " "
         << to_string(best->config.encoding) << " tol " << sci(best->config.tolerance) << " (max error "
         << sci(best->max_error) << ", " << bytes_text(best->bytes) << ", bake " << seconds_text(best->bake_seconds)
         << ").\n";
    else md << "none in this sweep.\n";
  }
  md << "<!-- /summary -->\n\n";
  if (!plot.empty()) md << "![max error vs bytes and bake time](" << plot << ")\n\n";

  md << "| resolution | mappings | encoding | tolerance | bytes | file bytes | bake s | lookup ns | max error | "
        "RMS error | max stored error |\n";
  md << "|---|---|---|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const TradeoffRow& r : rows)
    md << "| " << resolution_text(r.config.resolution) << " | " << mappings_text(r.config.mappings) << " | "
       << to_string(r.config.encoding) << " | " << sci(r.config.tolerance) << " | " << r.bytes << " | " << r.file_bytes
       << " | " << fmt("%.3g", r.bake_seconds) << " | " << fmt("%.0f", r.lookup_ns) << " | " << fmt("%.3g", r.max_error)
       << " | " << fmt("%.3g", r.rms_error) << " | " << fmt("%.3g", r.max_stored_error)
       << (r.unconverged ? " (" + std::to_string(r.unconverged) + " unconverged)" : std::string()) << " |\n";
  return md.str();
}

// --- The plot ---------------------------------------------------------------------------------
// A tiny raster plotter: RGB canvas, Bresenham lines, a built-in 5x7 bitmap font (upper case,
// digits and a few symbols; lower case is drawn as upper case), PNG through libpng's simplified
// API (no setjmp).

namespace {

using namespace plot;  // Canvas, Rgb, palette, LogAxis, Panel, draw_log_axes (reports/plot.h)

void draw_panel(Canvas& cv, const Panel& p, const TradeoffReport& report, const std::vector<double>& xs,
                const std::string& x_label, const std::vector<int>& series, const std::vector<int>& shapes) {
  std::vector<double> ys;
  for (const TradeoffRow& r : report.rows) ys.push_back(r.max_error);
  const LogAxis ax = LogAxis::of(xs), ay = LogAxis::of(ys);
  auto px = [&](double v) { return p.x0 + static_cast<int>(std::lround(ax.t(v) * (p.x1 - p.x0))); };
  auto py = [&](double v) { return p.y1 - static_cast<int>(std::lround(ay.t(v) * (p.y1 - p.y0))); };
  draw_log_axes(cv, p, ax, ay, x_label, "max |lookup - reference|");
  // Series: lines joining the resolutions of one series and tolerance, then the markers on top.
  const auto& rows = report.rows;
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (series[k] == series[k - 1] && shapes[k] == shapes[k - 1]) {
      const Rgb c = kPalette[series[k] % 8];
      const Rgb light{static_cast<std::uint8_t>((c.r + 255) / 2), static_cast<std::uint8_t>((c.g + 255) / 2),
                      static_cast<std::uint8_t>((c.b + 255) / 2)};
      cv.line(px(xs[k - 1]), py(rows[k - 1].max_error), px(xs[k]), py(rows[k].max_error), light, 2);
    }
  for (std::size_t k = 0; k < rows.size(); ++k)
    cv.marker(px(xs[k]), py(rows[k].max_error), shapes[k], kPalette[series[k] % 8]);
}

std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace

void write_tradeoff_plot(const TradeoffReport& report, const std::string& path) {
  check_writable(path);
  // Series (colour) = mapping set x encoding; marker = tolerance, in order of first appearance.
  std::vector<std::string> series_names;
  std::vector<double> tolerances;
  std::vector<int> series, shapes;
  for (const TradeoffRow& r : report.rows) {
    const std::string name = mappings_text(r.config.mappings) + " " + to_string(r.config.encoding);
    auto s = std::find(series_names.begin(), series_names.end(), name);
    if (s == series_names.end()) s = series_names.insert(series_names.end(), name);
    series.push_back(static_cast<int>(s - series_names.begin()));
    auto t = std::find(tolerances.begin(), tolerances.end(), r.config.tolerance);
    if (t == tolerances.end()) t = tolerances.insert(tolerances.end(), r.config.tolerance);
    shapes.push_back(static_cast<int>(t - tolerances.begin()));
  }
  const int legend_rows = static_cast<int>(std::max(series_names.size(), tolerances.size()));
  Canvas cv(1400, 680 + 24 * legend_rows);
  const std::string title = report.model + "  law " + to_string(report.law) + ": table lookup error vs cost";
  cv.text((cv.width() - Canvas::text_width(title, 3)) / 2, 18, title, kBlack, 3);
  std::vector<double> bytes, seconds;
  for (const TradeoffRow& r : report.rows) {
    bytes.push_back(static_cast<double>(r.bytes));
    seconds.push_back(r.bake_seconds);
  }
  draw_panel(cv, {130, 70, 660, 530}, report, bytes, "bytes (value + error, in memory)", series, shapes);
  draw_panel(cv, {830, 70, 1340, 530}, report, seconds, "bake time (s, wall)", series, shapes);
  // Legend: colours on the left, markers on the right.
  int y = 640;
  cv.text(130, y - 24, "colour: mappings + encoding", kGrey);
  for (std::size_t s = 0; s < series_names.size(); ++s, y += 24) {
    cv.fill(130, y + 2, 160, y + 10, kPalette[s % 8]);
    cv.text(172, y, series_names[s], kBlack);
  }
  y = 640;
  cv.text(830, y - 24, "marker: cubature tolerance", kGrey);
  for (std::size_t t = 0; t < tolerances.size(); ++t, y += 24) {
    cv.marker(840, y + 6, static_cast<int>(t), kGrey);
    cv.text(862, y, "tol " + short_number(tolerances[t]), kBlack);
  }
  cv.text(130, cv.height() - 22,
          "points: " + std::to_string(report.reference.points.size()) +
              " reference directions. lines join the resolutions of a series and tolerance.",
          kGrey);

  plot::write_png(cv, path);
}

}  // namespace ganzfeld::reports
