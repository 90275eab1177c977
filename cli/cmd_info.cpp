// ganzfeld info: a table's metadata (docs/lut-format.md).
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "laws/registry.h"
#include "shapes/json.h"
#include "tables/bake.h"
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
                  table.format_version, table.version.c_str(), table.model.c_str(), to_string(table.law));
      std::printf("  error        %s (lookup error: validated bound of |lookup - law|, %s at %lld points the "
                  "table was not built from)\n",
                  format_number(table.lookup_error).c_str(),
                  table.format_version >= 2 ? "margin x the largest measured" : "measured", table.interpolation_checks);
      if (table.target_error > 0.0)
        std::printf("  target       lookup error <= %s within %llu value bytes\n", format_number(table.target_error).c_str(),
                    static_cast<unsigned long long>(table.target_bytes));
      std::printf("  frame        %s%s%s, %s interpolation\n", to_string(table.frame),
                  table.frame == tables::Frame::lobe ? ", peak " : "",
                  table.frame == tables::Frame::lobe ? to_string(table.peak) : "", to_string(table.interpolation));
      if (!table.model_content.empty()) std::printf("  model data   %s\n", table.model_content.c_str());
      for (const tables::Axis& a : table.axes)
        std::printf("  axis         %-12s [%s, %s] %d nodes, %s%s\n", a.name.c_str(), format_number(a.min).c_str(),
                    format_number(a.max).c_str(), a.count, to_string(a.mapping),
                    a.has_width() ? (" (width " + format_number(a.width) + ")").c_str() : "");
      std::printf("  encoding     %s, %llu value bytes\n  node error   %s (cubature + rounding at the nodes only)\n"
                  "  tolerance    %s\n  unconverged  %lld of %zu\n  command      %s\n",
                  to_string(table.encoding), static_cast<unsigned long long>(tables::value_bytes(table)),
                  format_number(table.max_error).c_str(), format_number(table.tolerance).c_str(), table.unconverged,
                  table.entries(), table.command.c_str());
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
