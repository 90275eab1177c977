#include <cstdio>
#include <iostream>

#include "cli/args.h"
#include "cli/commands.h"
#include "reports/verify.h"
#include "util/atomic_file.h"

namespace ganzfeld::cli {

namespace {
struct VerifyArgs {
  bool json = false;
  std::string markdown;
};
}  // namespace

void add_verify_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("verify", "check every printed closed form against cubature (docs/errata.md)");
  auto args = std::make_shared<VerifyArgs>();
  add_json_flag(*cmd, args->json);
  cmd->add_option("--markdown", args->markdown, "also write the errata report (markdown) to FILE");
  cmd->callback([&action, args] {
    action = [args] {
      const auto checks = run_verification();
      if (!args->markdown.empty()) {
        const std::string command = "ganzfeld verify --markdown docs/errata.md";
        write_text_atomically(args->markdown, errata_markdown(checks, command));
      }
      const bool passed = verification_passed(checks);
      if (args->json) {
        std::cout << verify_json(checks).dump(2) << "\n";
      } else {
        std::printf("%-28s %-8s %12s %12s %8s\n", "id", "status", "printed", "corrected", "points");
        for (const auto& c : checks) {
          char corrected[32] = "-";
          if (c.corrected_max_abs_error) std::snprintf(corrected, sizeof corrected, "%.2e", *c.corrected_max_abs_error);
          std::printf("%-28s %-8s %12.2e %12s %8ld\n", c.id.c_str(), c.erratum ? "erratum" : "matches", c.max_abs_error,
                      corrected, c.points);
        }
        std::printf("%s: every matching or corrected form agrees with cubature to %.0e\n", passed ? "PASSED" : "FAILED",
                    kAgreement);
      }
      return passed ? 0 : 1;
    };
  });
}

}  // namespace ganzfeld::cli
