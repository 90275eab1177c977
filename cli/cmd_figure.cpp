// ganzfeld figure: the Koenderink–Pont 2×2 panel of a model (rasterizer/figure.h), optionally next
// to a second model's; with --disk, the halfway-vector disk view of a model (data) and a second one
// (its fit) for several outgoing directions (reports/disk.h: Edwards et al.'s Fig. 13).
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/spec.h"
#include "rasterizer/figure.h"
#include "reports/disk.h"
#include "tables/exr_io.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {
struct FigureArgs {
  std::string model, compare, output;
  CacheArgs cache;
  int size = raster::FigureOptions{}.size;
  TableOptionArgs tables;
  bool json = false, quiet = false, disk = false;
  std::vector<double> theta_o = DiskOptions{}.theta_o_deg;
};
int draw_disk(const FigureArgs& args, const Model& data, const Model* fit, const util::Stopwatch& watch) {
  if (args.output.size() < 4 || args.output.substr(args.output.size() - 4) != ".png")
    throw InputError("--disk writes a PNG; -o '" + args.output + "' must end in .png");
  check_writable(args.output);
  DiskOptions options;
  options.theta_o_deg = args.theta_o;
  write_disk_figure(data, fit, options, args.output);
  if (args.json) {
    nlohmann::ordered_json doc{
        {"output", args.output}, {"model", args.model}, {"disk", true}, {"theta_o", args.theta_o}};
    if (fit) doc["compare"] = args.compare;
    doc["seconds"] = watch.seconds();
    std::cout << doc.dump(2) << "\n";
  } else if (!args.quiet) {
    std::printf("disk view %s%s%s in %.2f s -> %s\n", args.model.c_str(), fit ? " vs " : "", args.compare.c_str(),
                watch.seconds(), args.output.c_str());
  }
  return 0;
}

}  // namespace

void add_figure_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "figure", "the Koenderink-Pont 2x2 panel: indicatrix, collimated, hemispherical and Ganzfeld sphere");
  auto args = std::make_shared<FigureArgs>();
  add_model_option(*cmd, args->model);
  cmd->add_option("-o,--output", args->output, "the panel, PANEL.png (sRGB) or PANEL.exr (linear); written atomically")
      ->required();
  cmd->add_option("--compare", args->compare, "a second model spec, drawn as a second panel on the right");
  cmd->add_option("--size", args->size, "pixels per quadrant side, 16..4096 (default 256)");
  args->tables.add_to(*cmd, raster::FigureOptions{}.tables);  // the small tables of g and h
  args->cache.add_to(*cmd);
  cmd->add_flag("--disk", args->disk,
                "the halfway-vector disk view instead: --model as the data (red), --compare as its fit (blue)");
  cmd->add_option("--theta-o", args->theta_o, "--disk: outgoing angles in degrees (default 0,15,30,45,60,75)")
      ->delimiter(',');
  cmd->add_flag("--quiet", args->quiet, "no summary line");
  add_json_flag(*cmd, args->json);
  cmd->callback([&action, args] {
    action = [args] {
      const util::Stopwatch watch;
      // Refuse bad input before any work.
      const ModelPtr model = parse_model(args->model);
      const ModelPtr compare = args->compare.empty() ? nullptr : parse_model(args->compare);
      if (args->disk) return draw_disk(*args, *model, compare.get(), watch);
      raster::FigureOptions options;
      options.tables = args->tables.options(options.tables);
      raster::image_format(args->output);
      check_writable(args->output);
      options.size = args->size;
      options.store = args->cache.store(args->quiet || args->json);
      std::vector<raster::Image> panels{raster::koenderink_pont_panel(args->model, options)};
      if (!args->compare.empty()) panels.push_back(raster::koenderink_pont_panel(args->compare, options));
      const raster::Image image = panels.size() == 1 ? panels.front() : raster::side_by_side(panels);
      raster::write_image(image, args->output);
      const double seconds = watch.seconds();
      if (args->json) {
        nlohmann::ordered_json doc{{"output", args->output}, {"model", args->model}};
        if (!args->compare.empty()) doc["compare"] = args->compare;
        doc["width"] = image.width;
        doc["height"] = image.height;
        doc["seconds"] = seconds;
        std::cout << doc.dump(2) << "\n";
      } else if (!args->quiet) {
        std::printf("figure %s%s%s, %dx%d in %.2f s -> %s\n", args->model.c_str(), args->compare.empty() ? "" : " vs ",
                    args->compare.c_str(), image.width, image.height, seconds, args->output.c_str());
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
