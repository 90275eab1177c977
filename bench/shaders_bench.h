// `ganzfeld bench shaders`: what shading from ganzfeld's tables costs in a fragment shader, beside
// what engines pay already, on whatever OpenGL implementation EGL finds (gl/context.h: a GPU's
// driver on the device platform, else Mesa's llvmpipe).
//
// One full-screen pass of size x size pixels into an RGBA16F target; every pixel its own normal n
// (the hemisphere facing the viewer, octahedrally mapped onto the square) and view j (a pinhole
// camera's ray), shaded by:
//   A  Lambert + a point light + ambient: the scene shader (export/glsl.h) of a Lambert material
//      under a collimated light and a Ganzfeld (closed forms: no table);
//   S  what engines pay for a glossy sky today: GGX with height-correlated Smith visibility and
//      Schlick Fresnel under the point light, plus split-sum image-based light (a prefiltered
//      cubemap with mips, one RG16F fetch of the DFG table ganzfeld bakes with --preset dfg, and
//      irradiance from 9 spherical-harmonic coefficients);
//   T  for every table set (a bake request: the scene defaults, --max-error E) and every variant its
//      exported GLSL offers (each `#ifdef GANZFELD_...` in it, and none): the scene shader of
//      0.8 lambert + 0.2 MODEL under the point light, a sky and a Ganzfeld: A with the lobe's f, g
//      and h on top, g and h from the set's tables.
// Per pass: milliseconds per frame (median, min, max of the timed frames after warm-up, interleaved
// across passes so that a load change hits every pass alike; GL_TIME_ELAPSED on a GPU, wall time
// around the draw and glFinish on a software renderer, whose timer queries miss rasterization),
// ratios to A and S, texture fetches per pixel (counted by the shader itself:
// gl::count_texture_fetches) and value bytes. Per table and variant: the largest
// |shader − tables::sample| (what `ganzfeld sample` prints) at points_side² seeded points read back
// from an RGBA32F target, beside the table's stated lookup error.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gl/context.h"
#include "integrate/laws.h"

namespace ganzfeld::bench {

struct ShadersBenchOptions {
  int size = 2048;       ///< the pass is size x size pixels
  int frames = 30;       ///< timed frames per pass
  int points_side = 64;  ///< accuracy: points_side² lookups per table and variant
  bool quick = false;    ///< small tables (seconds; CI's smoke test): fixed by quick_shaders_options
  gl::Platform platform = gl::Platform::automatic;
  std::string model = "specular:alpha=100";  ///< the glossy lobe of the T passes (a GLSL f is needed)
  std::string cache_dir;                     ///< where tables are kept between runs ("" = baked in memory)
};
/// --quick: 128² pixels, 30 frames, 32² points, small tables.
ShadersBenchOptions quick_shaders_options();
inline constexpr int kWarmupFrames = 3;
inline constexpr std::uint64_t kShaderPointSeed = 26;

/// One table of a T pass, judged at the lookup points.
struct LawLookup {
  Law law = Law::g;
  std::string scheme;         ///< export/glsl.h: lookup_scheme
  double lookup_error = 0.0;  ///< the table's stated error
  std::uint64_t value_bytes = 0;
  int fetches_min = 0, fetches_max = 0;  ///< per lookup, counted
  int points = 0;
  double max_difference = 0.0;  ///< max |shader − tables::sample|
};

struct ShaderPass {
  std::string name;                  ///< "A", "S", "T1", "T1 hw", ...
  std::string what;                  ///< what it shades, one line
  std::string table_set;             ///< T: the bake request; "" otherwise
  std::string define;                ///< T: the variant's #define, "" for none
  std::vector<double> milliseconds;  ///< per timed frame
  double fetches_mean = 0.0;
  int fetches_max = 0;  ///< per pixel, counted over a 256² pass
  std::uint64_t value_bytes = 0;
  std::vector<LawLookup> laws;  ///< T: g and h
};

struct ShadersBenchResult {
  gl::ContextInfo context;
  std::string timer;  ///< "GL_TIME_ELAPSED" or "wall time (glFinish)"
  int size = 0, frames = 0, points = 0;
  std::string model;
  std::vector<ShaderPass> passes;  ///< A, S, then T passes
};

/// Throws InputError for bad options (size, frames, model) and std::runtime_error when no GL
/// context can be made or a shader does not compile.
ShadersBenchResult run_shaders_benchmark(const ShadersBenchOptions& options);

/// The name of the result's section of docs/realtime.md: "shaders-software" for a CPU rasterizer,
/// "shaders-gpu" for a GPU (each kept beside the other).
std::string shaders_section(const ShadersBenchResult& result);

/// The section of docs/realtime.md: what ran where, the passes, the lookups' accuracy and the
/// GPU-cost targets of the tables (met/missed), stamped with `command` and today's date.
std::string shaders_markdown(const ShadersBenchResult& result, const std::string& command);

}  // namespace ganzfeld::bench
