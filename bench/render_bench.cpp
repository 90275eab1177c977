#include "bench/render_bench.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include "laws/spec.h"
#include "lut/bake.h"
#include "lut/plan.h"
#include "rasterizer/shading.h"

namespace ganzfeld::bench {

namespace {

double median_seconds(int repeats, const std::function<void()>& work) {
  std::vector<double> t;
  for (int k = 0; k < repeats; ++k) {
    const auto start = std::chrono::steady_clock::now();
    work();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

raster::RenderScene sphere_scene(int size) {
  raster::RenderScene rs;
  rs.camera.width = rs.camera.height = size;
  rs.meshes.push_back(raster::uv_sphere({0, 0, 0}, 1.0, raster::kSphereSegments));
  rs.mesh_material = {0};
  return rs;
}

}  // namespace

RenderBenchResult run_render_benchmark(bool quick) {
  RenderBenchResult out;
  out.size = quick ? 256 : 1024;
  out.crop = quick ? 32 : 64;
  const int repeats = quick ? 1 : 3;
  const Light sun{Light::Type::collimated, glm::normalize(Vec3{1, 1, 1}), {1, 1, 1}};
  const Light sky{Light::Type::hemispherical, {0, 1, 0}, {0.5, 0.5, 0.5}};
  const Light ambient{Light::Type::ganzfeld, {0, 0, 1}, {0.2, 0.2, 0.2}};

  // (a) Lambert + collimated + ambient constant.
  raster::RenderScene lambert = sphere_scene(out.size);
  lambert.lights = {sun, ambient};
  lambert.materials = {{{1.0, {0.8, 0.8, 0.8}, parse_model("lambert"), raster::lambert_laws()}}};

  // (b) the mixture under all three lights, from tables at the scene defaults.
  auto lobe_tables = [&](const char* spec) {
    const ModelPtr m = parse_model(spec);
    lut::BakeOptions g, h;
    g.resolution = {lut::kSceneResG[0], lut::kSceneResG[1], lut::kSceneResG[2]};
    h.resolution = {lut::kSceneResH};
    g.tolerance = h.tolerance = lut::kSceneTolerance;
    return raster::table_laws(std::make_shared<const lut::Table>(lut::bake(*m, Law::g, g)),
                              std::make_shared<const lut::Table>(lut::bake(*m, Law::h, h)));
  };
  const ModelPtr minnaert = parse_model("minnaert:xi=1"), specular = parse_model("specular:alpha=8");
  raster::RenderScene tables = sphere_scene(out.size);
  tables.lights = {sun, sky, ambient};
  tables.materials = {{{0.8, {0.2, 0.4, 0.8}, minnaert, lobe_tables("minnaert:xi=1")},
                       {0.2, {1, 1, 1}, specular, lobe_tables("specular:alpha=8")}}};

  // (c) the same, direct, on a crop (a smaller image of the same view: the per-pixel cost).
  raster::RenderScene direct = sphere_scene(out.crop);
  direct.lights = tables.lights;
  direct.materials = {{{0.8, {0.2, 0.4, 0.8}, minnaert, raster::direct_laws(minnaert, 1e-6)},
                       {0.2, {1, 1, 1}, specular, raster::direct_laws(specular, 1e-6)}}};

  out.seconds_lambert = median_seconds(repeats, [&] { raster::render(lambert); });
  out.seconds_tables = median_seconds(repeats, [&] { raster::render(tables); });
  out.seconds_direct = median_seconds(1, [&] { raster::render(direct); });
  const double pixels = double(out.size) * out.size, crop_pixels = double(out.crop) * out.crop;
  out.tables_vs_lambert = out.seconds_tables / out.seconds_lambert;
  out.direct_vs_tables = (out.seconds_direct / crop_pixels) / (out.seconds_tables / pixels);
  return out;
}

}  // namespace ganzfeld::bench
