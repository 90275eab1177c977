// `ganzfeld bench render`: does shading from tables cost about as much as Lambert + ambient,
// as Koenderink & Pont claim? One sphere mesh, rendered in one run:
//   (a) Lambert under a collimated beam + an ambient constant (a Lambertian Ganzfeld: h = 1)
//   (b) 0.8 minnaert:xi=1 + 0.2 specular:alpha=8 under collimated + sky + Ganzfeld, from tables
//       baked at the scene defaults (scene/plan.h: the scheme `bake scene` uses)
//   (c) the same as (b) with the laws integrated per pixel (--direct), on a small crop
// Each repeat renders (a), (b) and (c) side by side, so a change of load on a shared machine hits
// all three; the ratios are per repeat and per pixel: tables_vs_lambert = b/a (whole frames:
// rasterization and shading), direct_vs_tables = c/b per pixel. Table baking is not timed (tables
// are made once per material).
#pragma once

#include <string>
#include <vector>

namespace ganzfeld::bench {

struct RenderBenchResult {
  int size = 0, crop = 0, repeats = 0;
  std::vector<double> seconds_lambert, seconds_tables, seconds_direct;  ///< per repeat
  std::vector<double> tables_vs_lambert, direct_vs_tables;              ///< per repeat
  /// (b)'s tables: "law g of SPEC: " + exporting::lookup_scheme and the stated lookup error.
  std::vector<std::string> tables;
};

RenderBenchResult run_render_benchmark(bool quick, int repeats);

/// The section "render" of docs/realtime.md, stamped with `command` and today's date: medians and
/// spread, and the target tables ÷ Lambert ≤ 1.25 (met/missed).
std::string render_markdown(const RenderBenchResult& result, const std::string& command);

}  // namespace ganzfeld::bench
