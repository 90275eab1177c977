// ganzfeld plausibility: non-negativity, reciprocity, energy conservation and Ganzfeld
// invisibility measured for every model (reports/plausibility.h); --markdown writes
// docs/plausibility.md.
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "reports/plausibility.h"
#include "tables/exr_io.h"
#include "util/atomic_file.h"

namespace ganzfeld::cli {

namespace {
struct PlausibilityArgs {
  bool json = false;
  std::string markdown;
  double tol = 1e-6;
};
}  // namespace

void add_plausibility_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("plausibility",
                                 "measure min f, reciprocity, max albedo and Ganzfeld invisibility of every model");
  auto args = std::make_shared<PlausibilityArgs>();
  add_json_flag(*cmd, args->json);
  cmd->add_option("--markdown", args->markdown, "also write the report as Markdown (docs/plausibility.md)");
  cmd->add_option("--tol", args->tol, "absolute tolerance of the albedo and h integrals (default 1e-6)");
  cmd->callback([&action, args] {
    action = [args] {
      validate_tolerance(args->tol);
      if (!args->markdown.empty()) check_writable(args->markdown);
      const auto rows = plausibility_report(args->tol);
      if (!args->markdown.empty()) {
        std::vector<std::string> words{"ganzfeld", "plausibility", "--markdown", args->markdown};
        if (args->tol != 1e-6) words.insert(words.end(), {"--tol", format_number(args->tol)});
        const std::string command = shell_line(words);
        write_text_atomically(args->markdown, plausibility_markdown(rows, args->tol, command), "report");
      }
      if (args->json) {
        nlohmann::ordered_json doc{{"tolerance", args->tol}, {"models", nlohmann::ordered_json::array()}};
        for (const auto& r : rows)
          doc["models"].push_back({{"spec", r.spec},
                                   {"note", r.note},
                                   {"min_f", r.min_f},
                                   {"min_f_at", r.min_f_at},
                                   {"reciprocity_violation", r.reciprocity_violation},
                                   {"max_albedo", r.max_albedo},
                                   {"max_albedo_error", r.max_albedo_error},
                                   {"max_albedo_theta_i", r.max_albedo_theta_i},
                                   {"h_min", r.h_min},
                                   {"h_max", r.h_max},
                                   {"h_error", r.h_error},
                                   {"non_negative", r.non_negative()},
                                   {"reciprocal", r.reciprocal()},
                                   {"conserves", r.conserves()},
                                   {"ganzfeld_invisible", r.ganzfeld_invisible()},
                                   {"declared_reciprocal", r.declared.reciprocal},
                                   {"declared_energy_class", to_string(r.declared.energy)},
                                   {"traits_consistent", r.traits_consistent()},
                                   {"converged", r.converged},
                                   {"evaluations", r.evaluations}});
        std::cout << doc.dump(2) << "\n";
      } else {
        for (const auto& r : rows)
          std::printf("%-60s min f %-10.3g recip %-9.2g max a %-8.4g h %.4g..%.4g%s%s\n", r.spec.c_str(), r.min_f,
                      r.reciprocity_violation, r.max_albedo, r.h_min, r.h_max,
                      r.ganzfeld_invisible() ? " invisible" : "",
                      r.traits_consistent() ? "" : "  DECLARED TRAITS CONTRADICTED");
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
