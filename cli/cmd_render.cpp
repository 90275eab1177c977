// ganzfeld render: a scene file (cli-contract.md) to a linear EXR or an sRGB PNG. The scene decides
// which tables exist (lut/plan.h): only those are baked, or reused from --cache DIR (lut/cache.h,
// the same files `ganzfeld bake --scene SCENE --out DIR` makes with its defaults).
#include <chrono>
#include <optional>
#include <cstdio>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "laws/error.h"
#include "laws/registry.h"
#include "lut/bake.h"
#include "lut/cache.h"
#include "lut/exr_io.h"
#include "lut/plan.h"
#include "lut/scene.h"
#include "rasterizer/image.h"
#include "rasterizer/shading.h"

namespace ganzfeld::cli {

namespace {

// Table defaults are lut::kScene* (those of `ganzfeld bake --scene`), so a cache filled by
// either command is reused by the other.
/// Per-pixel tolerance of --direct: far below what an 8-bit PNG or the tables resolve.
constexpr double kDirectTol = 1e-6;

struct RenderArgs {
  std::string scene, output, cache;
  std::optional<double> tol;
  bool direct = false, json = false, quiet = false;
};

int run_render(const RenderArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  const double tol = args.tol.value_or(args.direct ? kDirectTol : lut::kSceneTolerance);
  validate_tolerance(tol);
  raster::image_format(args.output);  // refuse a bad extension or path before any work
  lut::check_writable(args.output);
  const Scene scene = load_scene(args.scene);
  raster::validate_camera(scene.camera);
  const std::string cache = args.cache.empty() ? std::string() : prepare_directory("--cache", args.cache);

  raster::RenderScene rs;
  rs.camera = scene.camera;
  rs.lights = scene.lights;
  raster::add_scene_geometry(scene, rs);

  // Law sources per lobe: Lambert closed forms; otherwise direct cubature or the tables the
  // scene needs (tables_needed lists each (spec, law) once).
  SceneTables scene_tables;
  if (!args.direct) scene_tables = prepare_scene_tables(scene, tol, cache, args.quiet || args.json);
  const auto& tables = scene_tables.tables;
  const nlohmann::ordered_json& tables_json = scene_tables.json;
  for (const Material& material : scene.materials) {
    raster::ShadingMaterial shading;
    for (const MaterialLobe& lobe : material.lobes) {
      raster::ShadingLobe s;
      s.weight = lobe.weight;
      s.color = lobe.color;
      s.model = lobe.model;
      if (raster::is_lambert(*lobe.model)) {
        s.laws = raster::lambert_laws();
      } else if (args.direct) {
        s.laws = raster::direct_laws(lobe.model, tol);
      } else if (!lobe.model->traits().isotropic) {
        s.laws = raster::direct_laws(lobe.model, kDirectTol);  // no tables for anisotropic models (lut/plan.h)
      } else {
        auto find = [&](Law law) -> std::shared_ptr<const lut::Table> {
          const auto it = tables.find({lobe.model->spec(), law});
          return it == tables.end() ? nullptr : it->second;
        };
        s.laws = raster::table_laws(find(Law::g), find(Law::h));
      }
      shading.push_back(std::move(s));
    }
    rs.materials.push_back(std::move(shading));
  }
  const raster::Image image = raster::render(rs);
  raster::write_image(image, args.output);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"output", args.output},
                                        {"width", image.width},
                                        {"height", image.height},
                                        {"shading", args.direct ? "direct" : "tables"},
                                        {"tolerance", tol},
                                        {"tables", tables_json},
                                        {"seconds", seconds}}
                     .dump(2)
              << "\n";
  } else if (!args.quiet) {
    std::printf("rendered %dx%d (%s, %zu tables) in %.2f s -> %s\n", image.width, image.height,
                args.direct ? "direct cubature" : "tables", tables.size(), seconds, args.output.c_str());
  }
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("render", "render a scene file to a linear EXR or an sRGB PNG");
  auto args = std::make_shared<RenderArgs>();
  cmd->add_option("--scene", args->scene, "the scene, SCENE.json (cli-contract.md)")->required();
  cmd->add_option("-o,--output", args->output,
                  "the image: IMAGE.exr (linear radiance, RGB float) or IMAGE.png (linear clamped to [0,1], sRGB "
                  "8-bit); written atomically")
      ->required();
  cmd->add_flag("--direct", args->direct,
                "shade g and h by cubature per pixel (the slow reference) instead of tables; Lambert lobes use their "
                "closed forms either way");
  cmd->add_option("--tol", args->tol,
                  "absolute tolerance: of the tables' cubature (default 1e-8), or per pixel with --direct (default "
                  "1e-6)");
  cmd->add_option("--cache", args->cache,
                  "reuse tables from DIR and store new ones there (created if its parent exists); the files of "
                  "`ganzfeld bake --scene SCENE --out DIR`. Default: bake in memory");
  cmd->add_flag("--quiet", args->quiet, "no progress and no summary line");
  cmd->add_flag("--json", args->json, "print one JSON document");
  cmd->callback([&action, args] { action = [args] { return run_render(*args); }; });
}

}  // namespace ganzfeld::cli
