#include "bench/render_bench.h"

#include <algorithm>
#include <vector>

#include "models/spec.h"
#include "scene/plan.h"
#include "rasterizer/shading.h"
#include "util/timing.h"

namespace ganzfeld::bench {

namespace {

double median_seconds(int repeats, const std::function<void()>& work) {
  return util::median(util::time_runs(repeats, work));
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
  // Planned as `render` plans a scene, with the scene defaults (scene/plan.h), in memory.
  auto lobe_tables = [&](const char* spec) {
    const scene::ShadingPlan plan =
        scene::plan_material(scene::material_of(spec), {sky, ambient}, scene::TableOptions{}, scene::TableStore{});
    return raster::shading_materials(plan, 1e-6).front().front().laws;
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
