#include "reports/schemes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "reports/plot.h"
#include "tables/bake.h"
#include "tables/frame.h"
#include "tables/sample.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::reports {

using namespace ganzfeld::tables;

const char* to_string(SchemeKind kind) {
  switch (kind) {
    case SchemeKind::today: return "today";
    case SchemeKind::max_error: return "max-error";
    case SchemeKind::swapped: return "other lookup";
    case SchemeKind::half: return "half";
    case SchemeKind::trilinear: return "trilinear";
    case SchemeKind::one_fetch: return "one-fetch";
    case SchemeKind::eight_fetch: return "eight-fetch";
  }
  return "?";
}

namespace {

/// What each kind bakes: fixed resolutions, --max-error targets (the last one of `targets` is
/// the pick the swapped and half rows start from; `stretch` after it, with its byte cap).
struct SchemePlan {
  std::vector<std::vector<int>> today, trilinear, one_fetch, eight_fetch;
  std::vector<double> targets;
  std::vector<double> unorm16_targets;  ///< bake --max-error E --encoding unorm16 (the 16-bit target)
  double stretch = 0.0;
  std::uint64_t stretch_bytes = 0;
  /// With one_fetch: the --max-error E [--max-bytes B] --fetches N picks (1e-3 in one fetch; 1e-4
  /// within 8 fetches and the target's 256 kB, so that a model that cannot meet it is refused
  /// there instead of searching up to the default cap).
  struct FetchTarget {
    double error;
    std::uint64_t bytes;
    int fetches;
  };
  std::vector<FetchTarget> fetch_targets;
};

SchemePlan scheme_plan(Law law, bool quick) {
  SchemePlan plan;
  if (law == Law::g) {
    plan.today = quick ? std::vector<std::vector<int>>{{9, 9, 5}, {17, 17, 9}}
                       : std::vector<std::vector<int>>{{17, 17, 9}, {33, 33, 17}};
    plan.trilinear = quick ? std::vector<std::vector<int>>{{9, 17, 5}}
                           : std::vector<std::vector<int>>{{13, 25, 9}, {17, 33, 13}, {25, 49, 17}};
    plan.one_fetch = quick ? std::vector<std::vector<int>>{{9, 17, 5}}
                           : std::vector<std::vector<int>>{{17, 33, 11}, {21, 41, 15}, {25, 49, 17}, {29, 57, 19}};
    plan.eight_fetch = quick ? std::vector<std::vector<int>>{{9, 17, 7}}
                             : std::vector<std::vector<int>>{{17, 33, 11}, {25, 49, 17}, {33, 65, 21}};
    plan.targets = quick ? std::vector<double>{1e-2} : std::vector<double>{1e-3, 1e-4};
    plan.unorm16_targets = quick ? std::vector<double>{1e-2} : std::vector<double>{1e-4};  // <= 128 kB in 16 bits
    if (!quick) plan.stretch = 1e-5, plan.stretch_bytes = 2'000'000;  // the stretch target: 1e-5 in 2 MB
    plan.fetch_targets = quick ? std::vector<SchemePlan::FetchTarget>{{kTrilinearTarget, 0, 1}}
                               : std::vector<SchemePlan::FetchTarget>{{kTrilinearTarget, 0, 1},
                                                                      {kEightFetchTarget, kEightFetchBytes, 8}};
  } else {
    plan.today = quick ? std::vector<std::vector<int>>{{9}} : std::vector<std::vector<int>>{{33}, {129}};
    plan.targets = quick ? std::vector<double>{1e-3} : std::vector<double>{1e-4, 1e-6};
  }
  return plan;
}

/// The options that bake `row` again at its own resolution (fixed rows, and the variants of a pick).
BakeOptions fixed_options(const SchemeRow& row, const Table* pick) {
  BakeOptions options;
  options.resolution = row.resolution;
  options.encoding = row.encoding;
  options.interpolation = row.interpolation;
  options.tolerance = pick ? pick->tolerance : kSchemeTolerance;
  options.filter = row.filter;
  if (row.frame == Frame::lobe && pick) options.lobe = LobeFrame{pick->peak, pick->axes[1].width};
  return options;
}

SchemeRow row_of(SchemeKind kind, std::vector<int> resolution, Frame frame = Frame::cosines) {
  SchemeRow row;
  row.kind = kind;
  row.resolution = std::move(resolution);
  row.frame = frame;
  return row;
}

/// Bakes `options` `repeats` times, fills the row from the table and the reference. A bake the
/// baker refuses (an error target it cannot reach, values outside the half range) leaves its
/// message in row.refused, worded as the rows' `bake` flags are, and nothing.
std::optional<Table> measure_row(const Model& model, Law law, const BakeRequest& options, int repeats,
                                 const Reference& reference, SchemeRow& row) {
  Table table;
  try {
    row.bake_seconds = util::time_runs(repeats, [&] { table = bake(model, law, options); });
  } catch (const InputError& refused) {
    row.refused = refused.worded(InputError::flag_spelling);
    return std::nullopt;
  }
  row.frame = table.frame;
  row.interpolation = table.interpolation;
  row.encoding = table.encoding;
  row.resolution = axis_counts(table.axes);
  row.value_bytes = value_bytes(table);
  row.fetches = fetches(table);
  row.filter = table.filter;
  row.lookup_error = table.lookup_error;
  // A hardware-filtered table is judged by the worst of the lookups a GPU may do (8-bit weights
  // rounded to nearest or truncated, or full precision), as its bound is.
  const std::vector<WeightRounding> roundings =
      table.filter == Filter::hardware
          ? std::vector<WeightRounding>{WeightRounding::exact, WeightRounding::nearest, WeightRounding::truncate}
          : std::vector<WeightRounding>{WeightRounding::exact};
  std::size_t covered = 0;
  double sum_sq = 0.0;
  row.max_error = 0.0;
  for (const ReferencePoint& p : reference.points) {
    double e = 0.0;
    for (WeightRounding r : roundings)
      e = std::max(e, std::abs(sample(table, p.direction.i, p.direction.j, r).value - p.value));
    covered += e <= table.lookup_error;
    sum_sq += e * e;
    row.max_error = std::max(row.max_error, e);
  }
  row.rms_error = reference.points.empty() ? 0.0 : std::sqrt(sum_sq / static_cast<double>(reference.points.size()));
  row.covered = reference.points.empty() ? 0.0 : static_cast<double>(covered) / reference.points.size();
  return table;
}

}  // namespace

SchemeReport measure_schemes(const Model& model, Law law, const SchemeOptions& options) {
  require_tabulated(law);
  if (!model.traits().isotropic)
    throw InputError("model '" + model.spec() + "' is anisotropic; tables exist only for isotropic models");
  if (options.repeats < 1)
    throw InputError({Named{"repeats", std::to_string(options.repeats)}, " is not allowed; expected an integer >= 1"});
  const util::Stopwatch start;
  SchemeReport report;
  report.model = model.spec();
  report.law = law;
  report.repeats = options.repeats;
  report.reference = compute_reference(model, law, options.points, options.seed, kSchemeReferenceTolerance,
                                       /*extremes=*/false, kSchemeMinCos);
  SchemePlan plan = scheme_plan(law, options.quick);
  if (options.one_fetch_only) {
    if (law != Law::g) throw InputError({Named{"one_fetch"}, " measures g tables only"});
    plan = SchemePlan{{}, {}, plan.one_fetch, plan.eight_fetch, {}, {}, 0.0, 0, plan.fetch_targets};
  }
  const std::optional<LobeFrame> lobe = law == Law::g ? lobe_frame_of(model) : std::nullopt;
  const std::size_t total = plan.today.size() + plan.targets.size() + plan.unorm16_targets.size() +
                            (plan.targets.empty() ? 0 : 2) + (plan.stretch > 0) + plan.trilinear.size() +
                            !plan.trilinear.empty() + plan.one_fetch.size() +
                            (plan.one_fetch.empty() ? 0 : 2 + plan.fetch_targets.size() + plan.eight_fetch.size());
  auto add = [&](const SchemeRow& row) {
    report.rows.push_back(row);
    if (options.progress) options.progress(report.rows.size(), total);
  };

  for (const std::vector<int>& resolution : plan.today) {
    SchemeRow row = row_of(SchemeKind::today, resolution);
    measure_row(model, law, fixed_options(row, nullptr), options.repeats, report.reference, row);
    add(row);
  }
  std::optional<Table> pick;
  struct Target {
    double error;
    std::uint64_t bytes;
    Encoding encoding;
  };
  std::vector<Target> targets;
  for (double target : plan.targets) targets.push_back({target, 0, Encoding::single});
  if (plan.stretch > 0) targets.push_back({plan.stretch, plan.stretch_bytes, Encoding::single});
  for (double target : plan.unorm16_targets) targets.push_back({target, 0, Encoding::unorm16});
  for (const auto& [target, bytes, encoding] : targets) {
    SchemeRow row = row_of(SchemeKind::max_error, {});
    row.target = target;
    row.target_bytes = bytes;
    row.encoding = encoding;
    TargetBake bake_options;
    bake_options.target = {target, bytes, 0};
    bake_options.encoding = encoding;
    std::optional<Table> table = measure_row(model, law, bake_options, options.repeats, report.reference, row);
    if (table && encoding == Encoding::single && target == plan.targets.back()) pick = std::move(table);
    add(row);
  }
  if (pick) {  // the pick with the other interpolation, and in half floats
    SchemeRow swapped = row_of(SchemeKind::swapped, axis_counts(pick->axes), pick->frame);
    swapped.interpolation =
        pick->interpolation == Interpolation::linear ? Interpolation::catmull_rom : Interpolation::linear;
    measure_row(model, law, fixed_options(swapped, &*pick), options.repeats, report.reference, swapped);
    add(swapped);
    SchemeRow half = row_of(SchemeKind::half, axis_counts(pick->axes), pick->frame);
    half.interpolation = pick->interpolation;
    half.encoding = Encoding::half;
    measure_row(model, law, fixed_options(half, &*pick), options.repeats, report.reference, half);
    add(half);
  }
  for (const std::vector<int>& resolution : plan.trilinear) {
    SchemeRow row = row_of(SchemeKind::trilinear, resolution);
    BakeOptions bake_options = fixed_options(row, nullptr);
    bake_options.lobe = lobe;
    measure_row(model, law, bake_options, options.repeats, report.reference, row);
    add(row);
  }
  if (!plan.trilinear.empty()) {  // in half floats: the smallest within kTrilinearTarget, else the finest
    const SchemeRow* base = &report.rows.back();
    for (const SchemeRow& r : report.rows)
      if (r.kind == SchemeKind::trilinear && r.refused.empty() && r.max_error <= kTrilinearTarget &&
          r.value_bytes < base->value_bytes)
        base = &r;
    SchemeRow row = row_of(SchemeKind::trilinear, base->resolution);
    row.encoding = Encoding::half;
    BakeOptions bake_options = fixed_options(row, nullptr);
    bake_options.lobe = lobe;
    measure_row(model, law, bake_options, options.repeats, report.reference, row);
    add(row);
  }
  if (!plan.one_fetch.empty()) {  // one hardware-filtered fetch: fixed resolutions, unorm16, and the --fetches 1 pick
    auto one_fetch_row = [&](const std::vector<int>& resolution, Encoding encoding, Filter filter) {
      SchemeRow row = row_of(SchemeKind::one_fetch, resolution, lobe ? Frame::warped : Frame::cosines);
      row.filter = filter;
      row.encoding = encoding;
      BakeOptions bake_options = fixed_options(row, nullptr);
      bake_options.lobe = lobe;
      bake_options.warped = lobe.has_value();
      measure_row(model, law, bake_options, options.repeats, report.reference, row);
      add(row);
    };
    for (const std::vector<int>& resolution : plan.one_fetch)
      one_fetch_row(resolution, Encoding::single, Filter::hardware);
    // The finest again read with texelFetch (2^D fetches, weights in full precision): what the 8-bit weights cost.
    one_fetch_row(std::vector<int>(report.rows.back().resolution), Encoding::single, Filter::texel_fetch);
    const SchemeRow* base = &report.rows.back();  // in unorm16: the smallest within kTrilinearTarget, else the finest
    for (const SchemeRow& r : report.rows)
      if (r.kind == SchemeKind::one_fetch && r.filter == Filter::hardware && r.refused.empty() &&
          r.max_error <= kTrilinearTarget && r.value_bytes < base->value_bytes)
        base = &r;
    one_fetch_row(std::vector<int>(base->resolution), Encoding::unorm16, Filter::hardware);
    for (const std::vector<int>& resolution : plan.eight_fetch) {  // the b-spline: 2 filtered fetches per axis
      SchemeRow row = row_of(SchemeKind::eight_fetch, resolution, lobe ? Frame::warped : Frame::cosines);
      row.filter = Filter::hardware;
      row.interpolation = Interpolation::bspline;
      BakeOptions bake_options = fixed_options(row, nullptr);
      bake_options.lobe = lobe;
      bake_options.warped = lobe.has_value();
      measure_row(model, law, bake_options, options.repeats, report.reference, row);
      add(row);
    }
    for (const auto& [target, bytes, budget] : plan.fetch_targets) {
      SchemeRow pick = row_of(SchemeKind::max_error, {});
      pick.target = target;
      pick.target_bytes = bytes;
      pick.target_fetches = budget;
      TargetBake pick_options;
      pick_options.target = {target, bytes, budget};
      measure_row(model, law, pick_options, options.repeats, report.reference, pick);
      add(pick);
    }
  }
  report.seconds = start.seconds();
  return report;
}

Spread bake_spread(const SchemeRow& row) {
  if (row.bake_seconds.empty()) return {};
  const auto [lo, hi] = std::minmax_element(row.bake_seconds.begin(), row.bake_seconds.end());
  return {util::median(row.bake_seconds), *lo, *hi};
}

namespace {

std::string number(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

}  // namespace

std::string scheme_label(const SchemeRow& row) {
  if (row.kind == SchemeKind::max_error)
    return "--max-error " + number("%g", row.target) +
           (row.target_bytes ? " --max-bytes " + std::to_string(row.target_bytes) : std::string()) +
           (row.target_fetches ? " --fetches " + std::to_string(row.target_fetches) : std::string()) +
           (row.encoding == Encoding::unorm16 ? " --encoding unorm16" : "");
  if (row.kind == SchemeKind::today || row.kind == SchemeKind::trilinear || row.kind == SchemeKind::one_fetch ||
      row.kind == SchemeKind::eight_fetch)
    return std::string(to_string(row.kind)) + " " + resolution_text(row.resolution) +
           (row.encoding == Encoding::half      ? " half"
            : row.encoding == Encoding::unorm16 ? " unorm16"
                                                : "") +
           (row.kind == SchemeKind::one_fetch && row.filter == Filter::texel_fetch ? " texelFetch" : "");
  return std::string(row.kind == SchemeKind::half ? "pick in half" : "pick, other lookup");
}

std::string schemes_markdown(const SchemeReport& report, const std::string& command, const std::string& plot) {
  std::ostringstream md;
  const Reference& ref = report.reference;
  md << "Measured by\n\n```sh\n"
     << command << "\n```\n\n"
     << "Reference: " << ref.points.size() << " seeded random points (seed " << ref.seed << ", "
     << (report.law == Law::g ? "j·n" : "cos θ") << " in [" << kSchemeMinCos << ", 1]) by cubature at "
     << number("%.0e", ref.tolerance) << " (largest error estimate " << number("%.2g", ref.max_error) << ", "
     << ref.unconverged << " unconverged), " << number("%.1f", ref.seconds) << " s; bake times: median [min–max] of "
     << report.repeats << " runs; whole run " << number("%.0f", report.seconds) << " s.\n\n";
  if (!plot.empty()) md << "![max error vs value bytes and bake time](" << plot << ")\n\n";
  md << "| scheme | frame | lookup | fetches | encoding | resolution | value bytes | bake s | max error | RMS error | "
        "stated lookup_error | covered |\n|---|---|---|--:|---|---|--:|--:|--:|--:|--:|--:|\n";
  for (const SchemeRow& r : report.rows) {
    md << "| " << scheme_label(r) << " | ";
    if (!r.refused.empty()) {
      md << "refused: " << r.refused << " | | | | | | | | | | |\n";
      continue;
    }
    const Spread t = bake_spread(r);
    md << to_string(r.frame) << " | " << to_string(r.interpolation)
       << (r.filter == Filter::hardware ? " (hardware filter)" : "") << " | " << r.fetches << " | "
       << to_string(r.encoding) << " | " << resolution_text(r.resolution) << " | " << r.value_bytes << " | "
       << number("%.3g", t.median) << " [" << number("%.3g", t.min) << "–" << number("%.3g", t.max) << "] | "
       << number("%.3g", r.max_error) << " | " << number("%.3g", r.rms_error) << " | " << number("%.3g", r.lookup_error)
       << " | " << number("%.2f", 100.0 * r.covered) << "% |\n";
  }
  return md.str();
}

void write_schemes_plot(const SchemeReport& report, const std::string& path) {
  using namespace plot;
  check_writable(path);
  std::vector<const SchemeRow*> rows;
  for (const SchemeRow& r : report.rows)
    if (r.refused.empty()) rows.push_back(&r);
  Canvas cv(1400, 720);
  const std::string title = report.model + "  law " + to_string(report.law) + ": lookup error vs cost, by scheme";
  cv.text((cv.width() - Canvas::text_width(title, 3)) / 2, 18, title, kBlack, 3);
  std::vector<double> bytes, seconds, errors;
  for (const SchemeRow* r : rows) {
    bytes.push_back(static_cast<double>(r->value_bytes));
    seconds.push_back(bake_spread(*r).median);
    errors.push_back(r->max_error);
  }
  const LogAxis ay = LogAxis::of(errors);
  for (const auto& [panel, xs, label] :
       {std::tuple{Panel{130, 70, 660, 530}, &bytes, "value bytes (what a shader uploads)"},
        std::tuple{Panel{830, 70, 1340, 530}, &seconds, "bake time (s, median)"}}) {
    const LogAxis ax = LogAxis::of(*xs);
    draw_log_axes(cv, panel, ax, ay, label, "max |lookup - reference|");
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const int x = panel.x0 + static_cast<int>(std::lround(ax.t((*xs)[k]) * (panel.x1 - panel.x0)));
      const int y = panel.y1 - static_cast<int>(std::lround(ay.t(errors[k]) * (panel.y1 - panel.y0)));
      const int kind = static_cast<int>(rows[k]->kind);
      cv.marker(x, y, kind, kPalette[kind % 8]);
    }
  }
  int y = 600;
  for (SchemeKind kind : {SchemeKind::today, SchemeKind::max_error, SchemeKind::swapped, SchemeKind::half,
                          SchemeKind::trilinear, SchemeKind::one_fetch, SchemeKind::eight_fetch}) {
    const int k = static_cast<int>(kind);
    cv.marker(140 + 175 * k, y + 6, k, kPalette[k % 8]);
    cv.text(156 + 175 * k, y, to_string(kind), kBlack);
  }
  cv.text(130, 650, "today: cosines frame, linear.  max-error: what bake --max-error picks.  other lookup, half: the",
          kGrey);
  cv.text(130, 674,
          "finest pick with the other interpolation or in half floats.  trilinear: lobe frame, linear.  "
          "one-fetch: warped frame, hardware filter.  eight-fetch: the same, b-spline.",
          kGrey);
  write_png(cv, path);
}

}  // namespace ganzfeld::reports
