// ganzfeld sample: a table lookup at given directions (tables/sample.h).
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "tables/exr_io.h"
#include "tables/sample.h"

namespace ganzfeld::cli {

namespace {
struct SampleArgs {
  std::string path;
  DirectionArgs directions;
  bool json = false;
};
}  // namespace

void add_sample_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "sample", "look a table up at directions (the table's interpolation in index space, clamped at the axis ends)");
  auto args = std::make_shared<SampleArgs>();
  cmd->add_option("FILE", args->path, "table written by `ganzfeld bake`")->required();
  args->directions.add_to(*cmd);
  cmd->add_flag("--json", args->json, "print one JSON document");
  cmd->callback([&action, args] {
    action = [args] {
      const tables::Table table = tables::read_table(args->path);
      const Law law = table.law;
      const bool needs_i = law == Law::g || law == Law::a;
      const bool needs_j = law == Law::g || law == Law::h;
      const Vec3 i = needs_i ? args->directions.incident(law) : Vec3{0, 0, 1};
      const Vec3 j = needs_j ? args->directions.outgoing(law) : Vec3{0, 0, 1};
      const tables::Sample s = tables::sample(table, i, j);
      if (args->json) {
        // error: the table's validated lookup error (docs/lut-format.md, "The error a lookup reports").
        nlohmann::ordered_json doc{{"value", s.value},
                                   {"error", table.lookup_error},
                                   {"node_error", s.error},
                                   {"validation_points", table.interpolation_checks}};
        std::cout << doc.dump(2) << "\n";
      } else {
        std::printf("%s %s = %.9g ± %.2g (the table's lookup error, validated at %lld points; node error here %.2g; "
                    "table %s)\n",
                    table.model.c_str(), to_string(law), s.value, table.lookup_error, table.interpolation_checks,
                    s.error, args->path.c_str());
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
