// ganzfeld export-brdf: any model as measured data (export/brdf_export.h) — a MERL binary file at
// MERL's 90x90x180 half/difference nodes, or ganzfeld's tabulated text format — so that readers,
// tables and renders of measured BRDFs can be tested against the analytic model they came from.
#include <iostream>

#include "cli/commands.h"
#include "util/error.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "export/brdf_export.h"

namespace ganzfeld::cli {

namespace {
struct ExportBrdfArgs {
  std::string model, format = "merl", res = "46x46x91", output;
};
}  // namespace

void add_export_brdf_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("export-brdf", "write a model as measured data: MERL binary or ganzfeld's tabulated text");
  auto args = std::make_shared<ExportBrdfArgs>();
  cmd->add_option("--model", args->model, "the model spec (single or mixture)")->required();
  cmd->add_option("--format", args->format, "merl (90x90x180 binary, as MERL's database) or tabulated (docs/measured.md)");
  cmd->add_option("--res", args->res, "tabulated: theta_i x theta_r x phi nodes (default 46x46x91: every 2 degrees)");
  cmd->add_option("-o,--output", args->output, "the file, written atomically")->required();
  cmd->callback([&action, args] {
    action = [args] {
      const ModelPtr model = parse_model(args->model);
      if (args->format == "merl") {
        exporting::write_merl(*model, args->output);
      } else if (args->format == "tabulated") {
        exporting::write_tabulated(*model, tables::parse_resolution(args->res, Law::g), args->output);
      } else {
        throw InputError("unknown --format '" + args->format + "'; allowed: merl, tabulated");
      }
      std::cout << "wrote " << args->output << " (" << args->format << ") from " << model->spec() << "\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
