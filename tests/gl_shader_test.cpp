// The exported shader in a real OpenGL implementation: Mesa's llvmpipe through EGL
// surfaceless — headless, no GPU, no window system. A fragment shader ray-casts the scene's
// spheres, shades each pixel with the exported ganzfeld_scene.glsl and the exported KTX2
// textures, and the pixels read back are compared with the software rasterizer's image of the
// same scene shaded from the same tables.
//
// The bound, per pixel and colour channel:
//   |GPU - CPU| <= sum over lights and lobes of |weight x colour x intensity| x
//                     (table node error + measured interpolation error)     [the table's stated error]
//                  + kFloatRelative x (sum of the same |terms| x |law value|) + kFloatAbsolute
// The first part is what the tables claim; the rest is single-precision arithmetic on the GPU
// (normals from a float ray cast, float axis mappings and interpolation weights, float pow in
// f) against double on the CPU. Both sample the same stored numbers, so in practice the
// difference is far below the first part, and the test holds every pixel to the float part
// alone as well: the GPU samples the tables the way tables/ does, not merely within their error.
// Measured on llvmpipe (Mesa 22.3): max |GPU - CPU| 4.9e-6, 3.5e-5 relative; 0.2% of the
// stated table error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>

#include <Imath/half.h>

#include "export/glsl.h"
#include "export/param_export.h"
#include "export/texture_file.h"
#include "gl/draw.h"
#include "models/spec.h"
#include "rasterizer/raster.h"
#include "rasterizer/shading.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/bake.h"
#include "tables/frame.h"
#include "tables/preset.h"
#include "tables/sample.h"
#include "tests/temp_dir.h"

namespace ganzfeld {
namespace {

constexpr double kFloatRelative = 2e-4;  // float pipeline vs double, relative to the shaded terms
constexpr double kFloatAbsolute = 1e-6;

constexpr const char* kSceneJson = R"({
  "camera": {"width": 128, "height": 128, "eye": [0, 0, 10], "target": [0, 0, 0],
             "up": [0, 1, 0], "fov_deg": 30, "background": [0, 0, 0]},
  "materials": {
    "plastic": {"lobes": [{"weight": 0.8, "model": "minnaert:xi=1",    "color": [0.15, 0.3, 0.8]},
                          {"weight": 0.2, "model": "specular:alpha=8", "color": [1, 1, 1]}]},
    "velvet":  {"model": "asperity:alpha=4", "color": [0.6, 0.1, 0.1]},
    "moon":    {"lobes": [{"weight": 0.5, "model": "backscatter:alpha=2", "color": [0.9, 0.9, 0.7]},
                          {"weight": 0.5, "model": "lambert",             "color": [0.5, 0.5, 0.5]}]},
    "chalk":   {"model": "minnaert:xi=0.3", "color": [0.9, 0.9, 0.9]}
  },
  "objects": [{"shape": "sphere", "center": [-1.1,  1.1, 0], "radius": 1, "material": "plastic"},
              {"shape": "sphere", "center": [ 1.1,  1.1, 0], "radius": 1, "material": "velvet"},
              {"shape": "sphere", "center": [-1.1, -1.1, 0], "radius": 1, "material": "moon"},
              {"shape": "sphere", "center": [ 1.1, -1.1, 0], "radius": 1, "material": "chalk"}],
  "lights": [{"type": "collimated",    "direction": [1, 1, 1],     "irradiance": [1, 1, 1]},
             {"type": "collimated",    "direction": [-1, 0, 0.3],  "irradiance": [0.4, 0.5, 0.6]},
             {"type": "hemispherical", "pole": [0.2, 0.9, 0.4],    "radiance": [0.3, 0.3, 0.3]},
             {"type": "ganzfeld",                                  "radiance": [0.1, 0.1, 0.1]}]
})";

/// The same scene with lobes whose tables `--max-error` bakes in format version 2: the lobe frame
/// (specular alpha = 100: mirror peak, backscatter alpha = 8: retro) and the cosines frame
/// (Minnaert, asperity), all Catmull–Rom (bake scene ... --max-error 1e-2). Minnaert xi = 0.3's
/// g cannot reach 1e-2 in the default byte cap, so the chalk becomes xi = 1.
std::string lobe_scene_json() {
  std::string json = kSceneJson;
  for (auto [from, to] :
       {std::pair{"specular:alpha=8", "specular:alpha=100"}, std::pair{"backscatter:alpha=2", "backscatter:alpha=8"},
        std::pair{"minnaert:xi=0.3", "minnaert:xi=1"}})
    json.replace(json.find(from), std::string(from).size(), to);
  return json;
}
constexpr double kLobeSceneMaxError = 1e-2;

// ---------------------------------------------------------------------------------------------
// GL plumbing (gl/: the context, programs, textures and framebuffers)

/// A current context on Mesa's surfaceless platform (llvmpipe: the renderer the bounds below were
/// measured on), GLSL 4.30 core or ES 3.00.
std::unique_ptr<gl::Context> make_context(bool es, std::string& error) {
  auto context = gl::make_context(es ? gl::Api::es30 : gl::Api::core43, gl::Platform::surfaceless, error);
  if (context)
    std::printf("GL renderer: %s | %s\n", context->info().gl_renderer.c_str(), context->info().gl_version.c_str());
  return context;
}

std::string vertex_source(bool es) { return gl::fullscreen_vertex_shader(es ? gl::Api::es30 : gl::Api::core43); }

/// Full-screen triangle; the fragment shader ray-casts spheres with the camera of
/// raster::pixel_ray and shades them with gz_scene_radiance. The ray-sphere intersection is the
/// numerically stable form (Haines et al., "Precision Improvements for Ray/Sphere
/// Intersection", Ray Tracing Gems, 2019): the normal is built from the closest-approach
/// vector, not from a large t.
std::string fragment_source(const std::string& version, bool hardware_filter, const std::string& scene_glsl) {
  return "#version " + version + "\n" + (hardware_filter ? "#define GANZFELD_HARDWARE_FILTER\n" : "") + scene_glsl + R"(
uniform vec3 u_eye;
uniform vec3 u_forward;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec2 u_scale;   // (tan(fov/2) aspect, tan(fov/2))
uniform vec2 u_size;    // image width, height
uniform int u_sphere_count;
uniform vec4 u_spheres[8];   // centre, radius
uniform int u_materials[8];
out vec4 out_color;
void main() {
  float x = gl_FragCoord.x;               // pixel centre, x + 0.5
  float y = u_size.y - gl_FragCoord.y;    // top row first, y + 0.5
  float u = (2.0 * x / u_size.x - 1.0) * u_scale.x;
  float v = (1.0 - 2.0 * y / u_size.y) * u_scale.y;
  vec3 d = normalize(u_forward + u * u_right + v * u_up);
  float best = 1e30;
  int hit = -1;
  vec3 normal = vec3(0.0, 0.0, 1.0);
  for (int s = 0; s < u_sphere_count; ++s) {
    vec3 oc = u_eye - u_spheres[s].xyz;
    float r = u_spheres[s].w;
    float tc = -dot(oc, d);
    vec3 q = oc + tc * d;                 // closest approach, relative to the centre
    float h2 = r * r - dot(q, q);
    if (h2 < 0.0) continue;
    float h = sqrt(h2);
    float t = tc - h;
    if (t > 0.0 && t < best) { best = t; hit = s; normal = normalize(q - h * d); }
  }
  if (hit < 0) { out_color = vec4(0.0); return; }
  out_color = vec4(gz_scene_radiance(u_materials[hit], normal, -d), 1.0);
}
)";
}

/// Exports `table` as KTX2 (what a user gets), reads the file back and uploads it to texture
/// unit `unit`, bound to the program's sampler uniform `sampler`.
gl::Texture upload_table(const tables::Table& table, const std::filesystem::path& dir, const std::string& sampler,
                         const gl::Program& program, int unit, bool hardware_filter) {
  const auto file = dir / (sampler + ".ktx2");
  exporting::write_texture(table, exporting::TextureFormat::ktx2, file.string(), sampler);
  const exporting::TextureData data = exporting::read_ktx2(file.string());
  EXPECT_EQ(data.key_values.at("ganzfeld.model"), table.model);
  gl::Texture texture = gl::upload_texture(data, table.law == Law::g, unit, hardware_filter);
  const GLint location = program.uniform(sampler.c_str());
  EXPECT_GE(location, 0) << sampler << " is not a uniform of the exported shader";
  glUniform1i(location, unit);
  return texture;
}

// ---------------------------------------------------------------------------------------------

struct Baked {
  Scene scene;
  scene::ShadingPlan plan;  // the planner's, as render and export-glsl --scene use it
  std::map<std::pair<std::string, Law>, std::shared_ptr<const tables::Table>> tables;
};

/// The scene's tables at the test's resolutions, or baked to `max_error` (> 0) as bake scene
/// --max-error does.
Baked bake_scene(const std::filesystem::path& dir, tables::Encoding encoding, const std::string& json,
                 double max_error) {
  const auto scene_path = dir / "scene.json";
  std::ofstream(scene_path) << json;
  Baked out{load_scene(scene_path.string()), {}, {}};
  scene::TableOptions options{{17, 17, 9}, {33}, 1e-7, CubatureOptions{}.max_evaluations, encoding};
  if (max_error > 0.0) options.target = tables::ErrorTarget{max_error, 0, 0};
  out.plan = scene::plan_shading(out.scene, options, scene::TableStore{});
  for (const scene::PlannedTable& t : out.plan.tables) out.tables[{t.request.spec, t.request.law}] = t.table;
  return out;
}

/// The software rasterizer's picture and its G-buffer (which pixels it covers).
struct CpuPicture {
  raster::Image image;
  raster::GBuffer gbuffer;
  raster::RenderScene render_scene;
};

CpuPicture cpu_render(const Baked& baked) {
  CpuPicture out;
  raster::RenderScene& rs = out.render_scene;
  rs = raster::render_scene(baked.scene, baked.plan, 1e-6);
  out.gbuffer = raster::rasterize(rs.camera, rs.meshes);
  out.image = raster::shade_image(rs, out.gbuffer);
  return out;
}

/// Per pixel and channel: the stated-error part and the float part of the bound (file comment),
/// from the CPU's own geometry (the laws' values are the CPU's table lookups).
std::array<double, 2> pixel_bound(const Baked& baked, const CpuPicture& cpu, int x, int y, int channel) {
  const raster::Fragment& f = cpu.gbuffer.at(x, y);
  const Material& material = baked.scene.materials[baked.scene.objects[f.mesh].material];
  double stated = 0.0, magnitude = 0.0;
  for (const Light& light : baked.scene.lights) {
    for (const MaterialLobe& lobe : material.lobes) {
      const double scale = std::abs(lobe.weight * lobe.color[channel] * light.intensity[channel]);
      Law law = Law::f;
      if (light.type == Light::Type::hemispherical) law = Law::g;
      if (light.type == Light::Type::ganzfeld) law = Law::h;
      const auto it = baked.tables.find({lobe.spec, law});
      if (it != baked.tables.end()) {
        const tables::Table& t = *it->second;
        stated += scale * std::max(t.lookup_error, t.node_error + t.interpolation_error);
      }
      magnitude += scale;
    }
  }
  // |law value| <= its own magnitude; the image value bounds the sum of the non-negative terms.
  magnitude = std::max(magnitude, static_cast<double>(cpu.image.at(x, y)[channel]));
  return {stated, kFloatRelative * magnitude + kFloatAbsolute};
}

struct Comparison {
  int compared = 0, coverage_mismatch = 0, covered_cpu = 0, over_bound = 0, over_float = 0;
  double max_difference = 0.0, max_relative = 0.0, max_over_stated = 0.0;
};

/// hardware_filter: the GPU's own linear filter (export/glsl.h) instead of texelFetch; it blends
/// with low-precision weights, so only the stated bound is asserted and the difference reported.
/// json, max_error: the scene and bake_scene's max_error.
void run_gl_comparison(bool es, tables::Encoding encoding, bool hardware_filter = false,
                       const std::string& json = kSceneJson, double max_error = 0.0) {
  std::string error;
  auto gl = make_context(es, error);
  ASSERT_TRUE(gl) << error;

  const auto dir = std::filesystem::path(testing_support::temp_dir()) /
                   (std::string(es ? "es" : "core") + "_" + to_string(encoding) + (max_error > 0.0 ? "_v2" : ""));
  std::filesystem::create_directories(dir);
  const Baked baked = bake_scene(dir, encoding, json, max_error);
  const CpuPicture cpu = cpu_render(baked);

  // Export exactly what a user gets: the scene shader and one KTX2 per table, read back from disk.
  const std::string scene_glsl = exporting::glsl_scene_shader(baked.scene, baked.plan, "gl_shader_test scene");

  std::string log;
  const gl::Program program = gl::link_program(
      vertex_source(es), fragment_source(es ? "300 es" : "430 core", hardware_filter, scene_glsl), log);
  ASSERT_TRUE(program) << log;
  glUseProgram(program.id());

  int unit = 0;
  std::vector<gl::Texture> textures;
  for (const auto& [key, table] : baked.tables)
    textures.push_back(upload_table(*table, dir, exporting::glsl_sampler_name(key.first, key.second), program, unit++,
                                    hardware_filter));

  const Camera& camera = baked.scene.camera;
  const Vec3 forward = glm::normalize(camera.target - camera.eye);
  const Vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const Vec3 up = glm::cross(right, forward);
  const double tan_half = std::tan(camera.fov_deg * std::numbers::pi / 360.0);
  auto set3 = [&](const char* name, const Vec3& v) {
    glUniform3f(program.uniform(name), static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
  };
  set3("u_eye", camera.eye);
  set3("u_forward", forward);
  set3("u_right", right);
  set3("u_up", up);
  glUniform2f(program.uniform("u_scale"), static_cast<float>(tan_half * camera.width / camera.height),
              static_cast<float>(tan_half));
  glUniform2f(program.uniform("u_size"), static_cast<float>(camera.width), static_cast<float>(camera.height));
  std::vector<float> spheres;
  std::vector<int> materials;
  for (const SceneObject& object : baked.scene.objects) {
    spheres.insert(spheres.end(), {static_cast<float>(object.center.x), static_cast<float>(object.center.y),
                                   static_cast<float>(object.center.z), static_cast<float>(object.radius)});
    materials.push_back(static_cast<int>(object.material));
  }
  glUniform1i(program.uniform("u_sphere_count"), static_cast<int>(materials.size()));
  glUniform4fv(program.uniform("u_spheres"), static_cast<GLsizei>(materials.size()), spheres.data());
  glUniform1iv(program.uniform("u_materials"), static_cast<GLsizei>(materials.size()), materials.data());

  const gl::Framebuffer target(camera.width, camera.height, GL_RGBA32F);
  ASSERT_TRUE(target.complete());
  const gl::VertexArray vertices;
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  const std::vector<float> pixels = target.read_rgba();
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

  Comparison c;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float* gpu = &pixels[(static_cast<std::size_t>(camera.height - 1 - y) * camera.width + x) * 4];
      const bool gpu_hit = gpu[3] > 0.5f;
      const bool cpu_hit = cpu.gbuffer.at(x, y).mesh != raster::Fragment::kNone;
      c.covered_cpu += cpu_hit;
      if (gpu_hit != cpu_hit) {
        ++c.coverage_mismatch;
        continue;
      }
      if (!cpu_hit) continue;
      ++c.compared;
      for (int k = 0; k < 3; ++k) {
        const double expected = cpu.image.at(x, y)[k];
        const double difference = std::abs(gpu[k] - expected);
        const auto [stated, floating] = pixel_bound(baked, cpu, x, y, k);
        if (difference > c.max_difference && std::getenv("GZ_DEBUG"))
          std::printf("  max so far at (%d,%d) ch %d: gpu %.7g cpu %.7g, n.j %.6f\n", x, y, k, gpu[k], expected,
                      glm::dot(cpu.gbuffer.at(x, y).normal, cpu.gbuffer.at(x, y).view));
        c.max_difference = std::max(c.max_difference, difference);
        c.max_relative = std::max(c.max_relative, difference / std::max(expected, 1e-3));
        c.max_over_stated = std::max(c.max_over_stated, difference / std::max(stated, 1e-300));
        c.over_float += difference > floating;
        if (difference > stated + floating) {
          if (c.over_bound < 5)
            ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << k << ": GPU " << gpu[k] << ", CPU "
                          << expected << ", difference " << difference << " > bound " << stated + floating;
          ++c.over_bound;
        }
      }
    }
  std::printf(
      "%s, %s tables%s: %d pixels compared, max |GPU - CPU| = %.3g (relative %.3g, %.3g of the stated table "
      "error); coverage differs at %d of %d silhouette-ring pixels\n",
      es ? "GLSL ES 3.00" : "GLSL 4.30 core", to_string(encoding), hardware_filter ? ", hardware filtering" : "",
      c.compared, c.max_difference, c.max_relative, c.max_over_stated, c.coverage_mismatch, c.covered_cpu);
  EXPECT_EQ(c.over_bound, 0);
  if (!hardware_filter) { EXPECT_EQ(c.over_float, 0) << "pixels whose GPU value differs by more than float precision"; }
  EXPECT_GT(c.compared, camera.width * camera.height / 3);  // the four spheres fill most of the frame
  // The two pictures cover the same spheres: they may differ only on the silhouette (the CPU's
  // coverage is the inscribed 128-gon mesh, the GPU's the exact sphere).
  EXPECT_LT(c.coverage_mismatch, c.covered_cpu / 50);
}

// ---------------------------------------------------------------------------------------------
// One table's exported lookup against tables::sample, point by point (format version 2: the lobe
// frame, the sinh mappings, Catmull–Rom with its end rules; and linear lookup).
//
// Both sample the same stored numbers, so they differ only by float32 arithmetic. Its bound at a
// point x, from the CPU lookup S itself (double):
//   sum over axes d of max |S(y with y_d moved) - S(y)| over y_d +- kCoordinateError and over
//       the index coordinate u_d +- kIndexError,   + kSumError x max |value|
// y = the table's axis coordinates of x (tables::axis_coordinates). A wrong frame, mapping,
// width, end rule or node order moves a lookup by a sizeable part of a node step, far above it.

/// Angles (radians) and cosines computed in float from float vectors: ~20 roundings of 2^-24
/// relative on unit quantities and the Cephes atan kernel (2e-7 relative) within ~1e-6 absolute.
constexpr double kCoordinateError = 1e-6;
/// Index coordinates: the sinh mappings' log (GLSL ES 3.00 §4.5.1: absolute error < 2^-21 near
/// 1, 3 ulp elsewhere) divided by V (> 1.3 for these tables), a few ulps of u for the others.
constexpr double kIndexError = 1e-6;
/// The blend: up to 64 products with float weights (each a few roundings of O(1) polynomials),
/// summed in float: < 64 x 2^-24 of the largest |value| blended (Catmull–Rom's |weights| sum to
/// < 2 in 3-D).
constexpr double kSumError = 64.0 / (1 << 24);
/// unorm16: the GPU's code / 65535 (one rounding) inside the blend above, then offset + scale x
/// blend: two more roundings of 2^-24 relative to the largest |value|.
constexpr double kDequantizeError = 2.0 / (1 << 24);
/// Points per table: a 64 x 64 framebuffer, one lookup per pixel.
constexpr int kPointsSide = 64;
constexpr std::uint64_t kPointSeed = 15;  // seeded points (tables::validation_points) and frames

/// The warped frame's offset (tables/frame.h) is (1 + q/d)/2 of quantities known to
/// ~kCoordinateError, with d >= the warp's smallest width times |i⊥|: at the step (|i⊥| ~ 1) an
/// error in q moves it by up to that error / (2 width).
double coordinate_error(const tables::Table& table, std::size_t axis) {
  if (table.frame != tables::Frame::warped || axis != 1) return kCoordinateError;
  double narrowest = HUGE_VAL;
  for (const tables::WarpSample& w : table.warp.samples) narrowest = std::min({narrowest, w.along, w.across});
  return kCoordinateError * (1.0 + 0.5 / narrowest);
}

/// The float bound (above) at law coordinates x.
double float_bound(const tables::Table& table, std::span<const double> x) {
  const std::vector<double> y = tables::axis_coordinates(table, x);
  const double at = tables::sample_axes(table, y).value;
  double bound = 0.0, largest = 0.0;
  for (float v : table.value) largest = std::max(largest, static_cast<double>(std::abs(v)));
  for (std::size_t d = 0; d < y.size(); ++d) {
    const tables::Axis& axis = table.axes[d];
    const double u = axis.index_coordinate(y[d]);
    const double moved_by = coordinate_error(table, d);
    double worst = 0.0;
    for (double moved :
         {y[d] - moved_by, y[d] + moved_by, axis.coordinate(u - kIndexError), axis.coordinate(u + kIndexError)}) {
      std::vector<double> z = y;
      z[d] = moved;
      worst = std::max(worst, std::abs(tables::sample_axes(table, z).value - at));
    }
    bound += worst;
  }
  const double dequantize = table.encoding == tables::Encoding::unorm16 ? kDequantizeError : 0.0;
  return bound + (kSumError + dequantize) * largest;
}

/// A table of `spec` baked at a small resolution with the given frame and lookup (its numbers do
/// not matter here beyond being a real law's: both sides read the same stored values).
tables::Table small_table(const std::string& spec, Law law, std::vector<int> resolution,
                          tables::Interpolation interpolation, bool lobe,
                          tables::Encoding encoding = tables::Encoding::single, bool warped = false,
                          tables::Filter filter = tables::Filter::texel_fetch) {
  const auto model = parse_model(spec);
  tables::BakeOptions options;
  options.encoding = encoding;
  options.resolution = std::move(resolution);
  options.tolerance = 1e-6;
  options.interpolation = interpolation;
  options.warped = warped;
  options.filter = filter;
  if (lobe) options.lobe = tables::lobe_frame_of(*model);
  EXPECT_EQ(options.lobe.has_value(), lobe) << spec << " has no lobe frame";
  tables::Table table = tables::bake(*model, law, options);
  table.command = "gl_shader_test";
  return table;
}

/// Every point's GPU lookup within the float bound of tables::sample. Hardware filtering (one
/// linear fetch, or 3 per Catmull–Rom axis) too on llvmpipe, which filters float textures with
/// full-precision weights (docs/shaders.md); elsewhere within the table's stated lookup error (a
/// GPU may round filter weights to 8 bits).
void compare_lookups(const tables::Table& table, bool es, bool hardware_filter = false) {
  std::string error;
  auto gl = make_context(es, error);
  ASSERT_TRUE(gl) << error;
  const bool exact_filter = gl->info().gl_renderer.find("llvmpipe") != std::string::npos;
  const gl::LookupPoints points = gl::lookup_points(table.law, kPointsSide, kPointSeed);
  const std::vector<float> gpu =
      gl::table_function_at_points(table, points, es ? gl::Api::es30 : gl::Api::core43,
                                   hardware_filter ? "GANZFELD_HARDWARE_FILTER" : "",
                                   hardware_filter || table.filter == tables::Filter::hardware, error)
          .values;
  ASSERT_EQ(gpu.size(), points.x.size()) << error;
  int over = 0;
  double largest = 0.0, largest_bound = 0.0;
  // A table whose bound covers the hardware filter is read with texture() whatever the define:
  // the GPU must match the full-precision lookup or one of the 8-bit emulations (weights rounded
  // to nearest or truncated) to float precision.
  const bool filtered = table.filter == tables::Filter::hardware;
  for (std::size_t p = 0; p < gpu.size(); ++p) {
    double cpu = tables::sample(table, points.x[p]).value;
    if (filtered)
      for (tables::WeightRounding r : {tables::WeightRounding::nearest, tables::WeightRounding::truncate}) {
        const double emulated = tables::sample(table, points.x[p], r).value;
        if (std::abs(gpu[p] - emulated) < std::abs(gpu[p] - cpu)) cpu = emulated;
      }
    const double difference = std::abs(gpu[p] - cpu);
    const double bound =
        hardware_filter && !filtered && !exact_filter ? table.lookup_error : float_bound(table, points.x[p]);
    largest = std::max(largest, difference);
    largest_bound = std::max(largest_bound, difference / bound);
    if (difference > bound && over++ < 5)
      ADD_FAILURE() << "point " << p << " (" << points.x[p][0]
                    << (points.x[p].size() > 1
                            ? ", " + std::to_string(points.x[p][1]) + ", " + std::to_string(points.x[p][2])
                            : "")
                    << "): GPU " << gpu[p] << ", CPU " << cpu << ", difference " << difference << " > " << bound;
  }
  std::printf("%s, law %s of %s, %s frame, %s%s: %zu points, max |GPU - CPU| = %.3g, %.3g of the bound\n",
              es ? "GLSL ES 3.00" : "GLSL 4.30 core", to_string(table.law), table.model.c_str(), to_string(table.frame),
              to_string(table.interpolation), hardware_filter || filtered ? " (hardware filter)" : "", gpu.size(),
              largest, largest_bound);
  EXPECT_EQ(over, 0);
}

TEST(GlShaderLookup, LobeFrameCatmullRomSpecularG) {
  const tables::Table table =
      small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::catmull_rom, true);
  compare_lookups(table, false);
  compare_lookups(table, true);
  compare_lookups(table, false, true);
}
TEST(GlShaderLookup, LobeFrameCatmullRomBackscatterG) {
  compare_lookups(small_table("backscatter:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::catmull_rom, true),
                  false);
}
TEST(GlShaderLookup, LobeFrameLinearSpecularG) {
  compare_lookups(small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::linear, true), true);
}
// The warped frame (version 4): its lookup read with texelFetch matches tables::sample to float
// precision; with the hardware filter its one texture() matches the full-precision lookup or an
// 8-bit emulation of it. specular alpha = 100 (an envelope), backscatter (retro peak) and ggx
// (no envelope), float and unorm16 (R16: desktop GL).
TEST(GlShaderLookup, WarpedFrameTexelFetchSpecularG) {
  const tables::Table table = small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::linear,
                                          true, tables::Encoding::single, true);
  ASSERT_GT(table.warp.envelope, 0.0);
  compare_lookups(table, false);
  compare_lookups(table, true);
}
TEST(GlShaderLookup, WarpedFrameHardwareFilterMatchesThe8BitEmulation) {
  for (const char* spec : {"specular:alpha=100", "backscatter:alpha=100", "ggx:roughness=0.3"}) {
    const tables::Table table = small_table(spec, Law::g, {10, 24, 8}, tables::Interpolation::linear, true,
                                            tables::Encoding::single, true, tables::Filter::hardware);
    compare_lookups(table, false);
    compare_lookups(table, true);
  }
  compare_lookups(small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::linear, true,
                              tables::Encoding::unorm16, true, tables::Filter::hardware),
                  false);
}
// The b-spline (version 6): its hardware lookup (2 filtered fetches per axis; llvmpipe filters in
// full precision, a GPU as the 8-bit emulation), float and unorm16, the warped frame's g and h; and
// a texel-fetch table read with texelFetch and under GANZFELD_HARDWARE_FILTER.
TEST(GlShaderLookup, BSplineHardwareFilterMatchesThe8BitEmulation) {
  for (const bool es : {false, true})
    compare_lookups(small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::bspline, true,
                                tables::Encoding::single, true, tables::Filter::hardware),
                    es);
  compare_lookups(small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::bspline, true,
                              tables::Encoding::unorm16, true, tables::Filter::hardware),
                  false);
  compare_lookups(small_table("specular:alpha=100", Law::h, {12}, tables::Interpolation::bspline, false,
                              tables::Encoding::single, false, tables::Filter::hardware),
                  true);
}
TEST(GlShaderLookup, BSplineTexelFetch) {
  const tables::Table g =
      small_table("backscatter:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::bspline, true);
  compare_lookups(g, false);
  compare_lookups(g, true, true);
  compare_lookups(small_table("asperity:alpha=4", Law::g, {8, 8, 6}, tables::Interpolation::bspline, false), false);
  compare_lookups(small_table("minnaert:xi=1", Law::h, {9}, tables::Interpolation::bspline, false), true);
}

TEST(GlShaderLookup, HardwareFilteredCosinesFrameAndH) {
  compare_lookups(small_table("asperity:alpha=4", Law::g, {8, 8, 6}, tables::Interpolation::linear, false,
                              tables::Encoding::single, false, tables::Filter::hardware),
                  false);
  compare_lookups(small_table("specular:alpha=100", Law::h, {12}, tables::Interpolation::linear, false,
                              tables::Encoding::single, false, tables::Filter::hardware),
                  true);
}
TEST(GlShaderLookup, CosinesFrameCatmullRomAsperityG) {
  compare_lookups(small_table("asperity:alpha=4", Law::g, {8, 8, 6}, tables::Interpolation::catmull_rom, false), false);
}
// unorm16 (GL_R16 codes, offset + scale in the function): desktop GL (GLSL ES 3.00 has R16 only
// with EXT_texture_norm16), texelFetch and hardware filtering.
TEST(GlShaderLookup, Unorm16LobeFrameCatmullRomSpecularG) {
  const tables::Table table = small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::catmull_rom,
                                          true, tables::Encoding::unorm16);
  ASSERT_GT(table.unorm.offset + table.unorm.scale, 0.0f);
  compare_lookups(table, false);
  compare_lookups(table, false, true);
}
TEST(GlShaderLookup, Unorm16LinearH) {
  compare_lookups(
      small_table("specular:alpha=100", Law::h, {12}, tables::Interpolation::linear, false, tables::Encoding::unorm16),
      false);
}
TEST(GlShaderLookup, CatmullRomH) {
  const tables::Table table =
      small_table("specular:alpha=100", Law::h, {12}, tables::Interpolation::catmull_rom, false);
  compare_lookups(table, false);
  compare_lookups(table, false, true);
}

// The texture fetches a lookup executes, counted by the shader itself (`bench shaders` reports
// them): per lookup 2^d texels blended linearly, 4^d by Catmull–Rom with texelFetch; with the
// hardware filter one linear fetch, or 3 per Catmull–Rom axis (export/glsl.h).
TEST(GlShaderLookup, FetchesPerLookupAreCounted) {
  std::string error;
  auto gl = make_context(false, error);
  ASSERT_TRUE(gl) << error;
  struct Case {
    tables::Table table;
    int texel_fetches, filtered_fetches;
  };
  const Case cases[] = {
      {small_table("specular:alpha=8", Law::g, {5, 6, 4}, tables::Interpolation::linear, false), 8, 1},
      {small_table("specular:alpha=100", Law::g, {10, 24, 8}, tables::Interpolation::catmull_rom, true), 64, 27},
      {small_table("minnaert:xi=1", Law::h, {9}, tables::Interpolation::linear, false), 2, 1},
      {small_table("minnaert:xi=1", Law::h, {9}, tables::Interpolation::catmull_rom, false), 4, 3},
      // the warped frame: 8 texel fetches read with texelFetch; a table whose bound covers the filter
      // is one texture() whatever the define (tables::fetches says the same)
      {small_table("specular:alpha=100", Law::g, {6, 9, 5}, tables::Interpolation::linear, true,
                   tables::Encoding::single, true),
       8, 1},
      {small_table("specular:alpha=100", Law::g, {6, 9, 5}, tables::Interpolation::linear, true,
                   tables::Encoding::single, true, tables::Filter::hardware),
       1, 1},
      // the b-spline: 4 coefficients per axis with texelFetch, 2 filtered fetches per axis
      {small_table("specular:alpha=8", Law::g, {6, 7, 6}, tables::Interpolation::bspline, false), 64, 8},
      {small_table("minnaert:xi=1", Law::h, {9}, tables::Interpolation::bspline, false), 4, 2},
      {small_table("specular:alpha=100", Law::g, {6, 9, 6}, tables::Interpolation::bspline, true,
                   tables::Encoding::single, true, tables::Filter::hardware),
       8, 8}};
  for (const Case& c : cases) {
    EXPECT_EQ(tables::fetches(c.table),
              c.table.filter == tables::Filter::hardware ? c.filtered_fetches : c.texel_fetches)
        << c.table.model;
    const gl::LookupPoints points = gl::lookup_points(c.table.law, 16, kPointSeed);
    for (bool filtered : {false, true}) {
      const gl::Lookups lookups =
          gl::table_function_at_points(c.table, points, gl::Api::core43, filtered ? "GANZFELD_HARDWARE_FILTER" : "",
                                       filtered || c.table.filter == tables::Filter::hardware, error);
      ASSERT_EQ(lookups.fetches.size(), points.x.size()) << error;
      for (int fetches : lookups.fetches)
        ASSERT_EQ(fetches, filtered ? c.filtered_fetches : c.texel_fetches)
            << c.table.model << " law " << to_string(c.table.law) << (filtered ? ", hardware filter" : ", texelFetch");
    }
  }
}

TEST(GlShader, CountTextureFetchesWrapsEveryCallOutsideComments) {
  const std::string source =
      "// texture(a, b) in a comment\n"
      "vec4 x = texture(s, vec2(texelFetch(t, ivec2(0), 0).r, 0.5));\n"
      "/* textureLod(c, d, 0.0) */ float textured = 1.0; float y = mytexture(s) + textureLod (c, r, 2.0).g;\n";
  EXPECT_EQ(gl::count_texture_fetches(source),
            "// texture(a, b) in a comment\n"
            "vec4 x = (gz_fetches += 1, texture(s, vec2((gz_fetches += 1, texelFetch(t, ivec2(0), 0)).r, 0.5)));\n"
            "/* textureLod(c, d, 0.0) */ float textured = 1.0; float y = mytexture(s) + "
            "(gz_fetches += 1, textureLod(c, r, 2.0)).g;\n");
}

TEST(GlShader, Glsl430CoreFloatTablesMatchTheSoftwareRasterizer) { run_gl_comparison(false, tables::Encoding::single); }
TEST(GlShader, Glsl430CoreHalfTablesMatchTheSoftwareRasterizer) { run_gl_comparison(false, tables::Encoding::half); }
TEST(GlShader, GlslEs300FloatTablesMatchTheSoftwareRasterizer) { run_gl_comparison(true, tables::Encoding::single); }
TEST(GlShader, Glsl430CoreUnorm16TablesMatchTheSoftwareRasterizer) {
  run_gl_comparison(false, tables::Encoding::unorm16);
}
// Format version 2 scene tables (lobe frame, Catmull–Rom), with texelFetch and hardware filtering.
TEST(GlShader, MaxErrorTablesMatchTheSoftwareRasterizer) {
  run_gl_comparison(false, tables::Encoding::single, false, lobe_scene_json(), kLobeSceneMaxError);
  run_gl_comparison(true, tables::Encoding::single, true, lobe_scene_json(), kLobeSceneMaxError);
}
TEST(GlShader, HardwareFilteringStaysWithinTheStatedTableError) {
  run_gl_comparison(false, tables::Encoding::single, true);
}

// ---------------------------------------------------------------------------------------------
// Parameter tables: the exported GLSL lookup, reading the exported C header's half
// texels, against tables::sample_param on the same half values, at points across and beyond
// both axes (the clamping), in GLSL 4.30 core and ES 3.00.

/// The header's texels, parsed back from its text (what an engine compiles in).
std::vector<std::uint16_t> header_texels(const std::string& header) {
  std::vector<std::uint16_t> bits;
  const std::size_t start = header.find("_texels[");
  for (std::size_t at = header.find("0x", start); at != std::string::npos; at = header.find("0x", at + 6))
    bits.push_back(static_cast<std::uint16_t>(std::stoul(header.substr(at, 6), nullptr, 16)));
  return bits;
}

void run_param_comparison(bool es, const tables::ParamTable& table) {
  std::string error;
  auto gl = make_context(es, error);
  ASSERT_TRUE(gl) << error;
  const std::string name = exporting::glsl_param_function_name(table);
  const std::vector<std::uint16_t> bits = header_texels(exporting::param_c_header(table, name));
  const int channels = static_cast<int>(table.channels.size()), width = table.axes[1].count,
            height = table.axes[0].count;
  ASSERT_EQ(bits.size(), static_cast<std::size_t>(width * height * channels));
  // The CPU lookup of exactly the header's values.
  tables::ParamTable halfed = table;
  for (std::size_t m = 0; m < table.entries(); ++m)
    for (int c = 0; c < channels; ++c) {
      Imath::half h;
      h.setBits(bits[m * channels + c]);
      halfed.channels[c].value[m] = h;
      // The header holds the table's values, rounded to half: unit roundoff 2^-11 relative, and
      // half the subnormal spacing 2^-24 below the normal range.
      EXPECT_LE(std::abs(halfed.channels[c].value[m] - table.channels[c].value[m]),
                0x1p-11 * std::abs(table.channels[c].value[m]) + 0x1p-25)
          << table.channels[c].name << " texel " << m;
    }
  constexpr int kSize = 33;  // query points: a 33 x 33 grid over [-0.05, 1.05]^2
  const std::string fragment = std::string("#version ") + (es ? "300 es\nprecision highp float;\n" : "430 core\n") +
                               exporting::glsl_param_snippet(table) + R"(
uniform highp sampler2D u_table;
out vec4 out_color;
void main() {
  vec2 q = (gl_FragCoord.xy - 0.5) / 32.0 * 1.1 - 0.05;
  out_color = )" + name + R"((u_table, q.x, q.y);
}
)";
  std::string log;
  const gl::Program program = gl::link_program(vertex_source(es), fragment, log);
  ASSERT_TRUE(program) << log;
  glUseProgram(program.id());
  GLuint id = 0;
  glGenTextures(1, &id);
  const gl::Texture texture(id);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const GLenum internal = channels == 3 ? GL_RGB16F : GL_RG16F, format = channels == 3 ? GL_RGB : GL_RG;
  glTexImage2D(GL_TEXTURE_2D, 0, internal, width, height, 0, format, GL_HALF_FLOAT, bits.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glUniform1i(program.uniform("u_table"), 0);
  const gl::Framebuffer target(kSize, kSize, GL_RGBA32F);
  ASSERT_TRUE(target.complete());
  const gl::VertexArray vertices;
  glDrawArrays(GL_TRIANGLES, 0, 3);
  const std::vector<float> pixels = target.read_rgba();
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  double max_difference = 0.0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < channels; ++c) {
        // The same point in double (the GPU computes it in float: within an ulp of this).
        const double mu = x / 32.0 * 1.1 - 0.05, p = y / 32.0 * 1.1 - 0.05;
        const double cpu = tables::sample_param(halfed, c, p, mu).value;
        const double gpu = pixels[(static_cast<std::size_t>(y) * kSize + x) * 4 + c];
        max_difference = std::max(max_difference, std::abs(gpu - cpu));
        EXPECT_LE(std::abs(gpu - cpu), kFloatRelative * std::abs(cpu) + kFloatAbsolute)
            << table.channels[c].name << " at mu " << mu << ", " << table.axes[0].name << " " << p;
      }
  std::printf("%s, %s (%s grid): max |GPU - CPU| = %.3g over %d points x %d channels\n",
              es ? "GLSL ES 3.00" : "GLSL 4.30 core", name.c_str(), to_string(table.grid), max_difference,
              kSize * kSize, channels);
}

tables::ParamTable small_preset(tables::Preset preset, tables::Grid grid, const char* axis) {
  tables::PresetOptions o;
  o.preset = preset;
  o.grid = grid;
  o.axis = axis;
  o.resolution = {6, 8};
  return tables::bake_preset(*parse_model("ggx"), o);
}

TEST(GlShader, DfgTableLookupMatchesTheCpu) {
  const tables::ParamTable dfg = small_preset(tables::Preset::dfg, tables::Grid::texel, tables::kAxisRoughness);
  run_param_comparison(false, dfg);
  run_param_comparison(true, dfg);
}

TEST(GlShader, KullaContyNodeTableLookupMatchesTheCpu) {
  run_param_comparison(false, small_preset(tables::Preset::kulla_conty, tables::Grid::node, tables::kAxisAlpha));
}

}  // namespace
}  // namespace ganzfeld
