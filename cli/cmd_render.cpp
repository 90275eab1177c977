// ganzfeld render: a scene file (examples/default.json) to a linear EXR or an sRGB PNG. The scene decides
// which tables exist (scene/plan.h): only those are baked, or reused from --cache DIR (tables/cache.h,
// the same files `ganzfeld bake scene SCENE --out DIR` makes with the same table options).
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "rasterizer/image.h"
#include "rasterizer/shading.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/bake.h"
#include "tables/cache.h"
#include "tables/exr_io.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {

/// Per-pixel tolerance of --direct (and of anisotropic lobes, which have no tables): far below
/// what an 8-bit PNG or the tables resolve.
constexpr double kDirectTol = 1e-6;

struct RenderArgs {
  std::string scene, output;
  CacheArgs cache;
  TableOptionArgs table;  // the same table options as `bake scene`, hence the same cache entries
  bool direct = false, json = false, quiet = false;
};

int run_render(const RenderArgs& args) {
  const util::Stopwatch watch;
  scene::TableOptions defaults = scene::TableOptions::scene_defaults();
  if (args.direct) defaults.tolerance = kDirectTol;
  const scene::TableOptions options = args.table.options(defaults);
  raster::image_format(args.output);  // refuse a bad extension or path before any work
  check_writable(args.output);
  const Scene scene = load_scene(args.scene);
  raster::validate_camera(scene.camera);

  const scene::ShadingPlan plan =
      scene::plan_shading(scene, options, args.cache.store(args.quiet || args.json), args.direct);
  warn_unconverged(plan);
  const double direct_tol = args.direct ? options.tolerance : kDirectTol;
  const raster::Image image = raster::render(raster::render_scene(scene, plan, direct_tol));
  raster::write_image(image, args.output);
  const double seconds = watch.seconds();
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"output", args.output},
                                        {"width", image.width},
                                        {"height", image.height},
                                        {"shading", args.direct ? "direct" : "tables"},
                                        {"tolerance", options.tolerance},
                                        {"tables", tables_json(plan)},
                                        {"seconds", seconds}}
                     .dump(2)
              << "\n";
  } else if (!args.quiet) {
    std::printf("rendered %dx%d (%s, %zu tables) in %.2f s -> %s\n", image.width, image.height,
                args.direct ? "direct cubature" : "tables", plan.tables.size(), seconds, args.output.c_str());
  }
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("render", "render a scene file to a linear EXR or an sRGB PNG");
  auto args = std::make_shared<RenderArgs>();
  cmd->add_option("--scene", args->scene, "the scene, SCENE.json (e.g. examples/default.json)")->required();
  cmd->add_option("-o,--output", args->output,
                  "the image: IMAGE.exr (linear radiance, RGB float) or IMAGE.png (linear clamped to [0,1], sRGB "
                  "8-bit); written atomically")
      ->required();
  cmd->add_flag("--direct", args->direct,
                "shade g and h by cubature per pixel (the slow reference) instead of tables; Lambert lobes use their "
                "closed forms either way");
  args->table.add_to(*cmd, scene::TableOptions::scene_defaults());  // with --direct, --tol is per pixel (default 1e-6)
  args->cache.add_to(*cmd);
  cmd->add_flag("--quiet", args->quiet, "no progress and no summary line");
  add_json_flag(*cmd, args->json);
  cmd->callback([&action, args] { action = [args] { return run_render(*args); }; });
}

}  // namespace ganzfeld::cli
