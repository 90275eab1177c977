// ganzfeld export-brdf: any model as measured data (export/brdf_export.h) — a MERL binary file at
// MERL's 90x90x180 half/difference nodes, or ganzfeld's tabulated text format — so that readers,
// tables and renders of measured BRDFs can be tested against the analytic model they came from.
#include <iostream>

#include "cli/commands.h"
#include "export/brdf_export.h"
#include "models/registry.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "util/error.h"

namespace ganzfeld::cli {

namespace {
struct ExportBrdfArgs {
  std::string model, format = "merl", res = "46x46x91", output;
  exporting::Noise noise;
};
}  // namespace

void add_export_brdf_command(CLI::App& app, Action& action) {
  auto* cmd =
      app.add_subcommand("export-brdf", "write a model as measured data: MERL binary or ganzfeld's tabulated text");
  auto args = std::make_shared<ExportBrdfArgs>();
  cmd->add_option("--model", args->model, "the model spec (single or mixture)")->required();
  cmd->add_option("--format", args->format,
                  "merl (90x90x180 binary, as MERL's database) or tabulated (docs/measured.md)");
  cmd->add_option("--res", args->res, "tabulated: theta_i x theta_r x phi nodes (default 46x46x91: every 2 degrees)");
  cmd->add_option("-o,--output", args->output, "the file, written atomically")->required();
  cmd->add_option("--noise", args->noise.sigma,
                  "multiplicative noise: each value times 1 + SIGMA z, z standard normal (default 0: exact)");
  cmd->add_option("--seed", args->noise.seed, "the noise generator's seed (default 1; the same seed, the same file)");
  cmd->callback([&action, args] {
    action = [args] {
      const ModelPtr model = parse_model(args->model);
      exporting::validate_noise(args->noise);
      if (args->format == "merl") {
        exporting::write_merl(*model, args->output, args->noise);
      } else if (args->format == "tabulated") {
        exporting::write_tabulated(*model, tables::parse_resolution(args->res, Law::g), args->output, args->noise);
      } else {
        throw InputError("unknown --format '" + args->format + "'; allowed: merl, tabulated");
      }
      std::cout << "wrote " << args->output << " (" << args->format << ") from " << model->spec();
      if (args->noise.sigma > 0.0)
        std::cout << " with noise sigma " << format_number(args->noise.sigma) << ", seed " << args->noise.seed;
      std::cout << "\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
