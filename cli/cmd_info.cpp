// ganzfeld info: a table's metadata (docs/lut-format.md).
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "laws/registry.h"
#include "shapes/json.h"
#include "tables/exr_io.h"

namespace ganzfeld::cli {

namespace {
struct InfoArgs {
  std::string path;
  bool json = false;
};
}  // namespace

void add_info_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("info", "metadata of a baked table (refuses files that are not valid tables)");
  auto args = std::make_shared<InfoArgs>();
  cmd->add_option("FILE", args->path, "table written by `ganzfeld bake`")->required();
  cmd->add_flag("--json", args->json, "print one JSON document");
  cmd->callback([&action, args] {
    action = [args] {
      const tables::Table table = tables::read_table(args->path);
      if (args->json) {
        std::cout << shapes::info_json(args->path, table).dump(2) << "\n";
        return 0;
      }
      std::printf("%s\n  format version %d, ganzfeld %s\n  model        %s\n  law          %s\n", args->path.c_str(),
                  tables::kFormatVersion, table.version.c_str(), table.model.c_str(), to_string(table.law));
      if (!table.model_content.empty()) std::printf("  model data   %s\n", table.model_content.c_str());
      for (const tables::Axis& a : table.axes)
        std::printf("  axis         %-12s [%s, %s] %d nodes, %s\n", a.name.c_str(), format_number(a.min).c_str(),
                    format_number(a.max).c_str(), a.count, to_string(a.mapping));
      std::printf("  encoding     %s\n  tolerance    %s\n  max error    %s (at the nodes)\n  interpolation error %s (measured at %lld cell centres)\n  unconverged  %lld of %zu\n  command      %s\n",
                  to_string(table.encoding), format_number(table.tolerance).c_str(),
                  format_number(table.max_error).c_str(), format_number(table.interpolation_error).c_str(),
                  table.interpolation_checks, table.unconverged, table.entries(), table.command.c_str());
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
