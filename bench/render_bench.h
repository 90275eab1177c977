// `ganzfeld bench render`: does shading from tables cost about as much as Lambert + ambient,
// as Koenderink & Pont claim? One sphere mesh, rendered in one run:
//   (a) Lambert under a collimated beam + an ambient constant (a Lambertian Ganzfeld: h = 1)
//   (b) 0.8 minnaert:xi=1 + 0.2 specular:alpha=8 under collimated + sky + Ganzfeld, from tables
//   (c) the same as (b) with the laws integrated per pixel (--direct), on a small crop
// Ratios are per pixel: tables_vs_lambert = b/a, direct_vs_tables = c/b. Table baking is not
// timed (tables are made once per material).
#pragma once

namespace ganzfeld::bench {

struct RenderBenchResult {
  int size = 0, crop = 0;
  double seconds_lambert = 0, seconds_tables = 0, seconds_direct = 0;  ///< per render (median)
  double tables_vs_lambert = 0, direct_vs_tables = 0;                  ///< per-pixel ratios
};

RenderBenchResult run_render_benchmark(bool quick);

}  // namespace ganzfeld::bench
