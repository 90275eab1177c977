// ganzfeld: extended-source shading tables from BRDFs. run_cli catches once and maps to the exit
// codes: 0 ok, 2 bad input (one line on stderr), 1 internal failure.
#include "cli/run.h"

#include <exception>
#include <iostream>

#include "cli/commands.h"
#include "util/error.h"

namespace ganzfeld::cli {

int run_cli(int argc, const char* const* argv, bool parse_only) {
  CLI::App app{"ganzfeld " GANZFELD_VERSION
               " - laws of shading, vignetting and darkening (Koenderink & Pont) for any BRDF"};
  app.set_version_flag("--version", GANZFELD_VERSION);
  app.require_subcommand(1, 1);
  Action action;
  add_models_command(app, action);
  add_eval_command(app, action);
  add_verify_command(app, action);
  add_bake_command(app, action, argc, argv);
  add_info_command(app, action);
  add_sample_command(app, action);
  add_tradeoff_command(app, action);
#ifdef GANZFELD_HAS_BENCH  // built only with -DGANZFELD_BENCH=ON (the peers are linked there)
  add_bench_command(app, action);
#else
  app.add_subcommand("bench", "not built (configure with -DGANZFELD_BENCH=ON)")->allow_extras()->callback([&action] {
    action = []() -> int {
      throw ganzfeld::InputError("this ganzfeld was built without the benchmark; configure with -DGANZFELD_BENCH=ON");
    };
  });
#endif
  add_render_command(app, action);
  add_figure_command(app, action);
  add_export_glsl_command(app, action);
  add_export_brdf_command(app, action);
  add_plausibility_command(app, action);
  add_serve_command(app, action);
  add_extremes_command(app, action);
#ifdef GANZFELD_HAS_FIT  // built only where NLopt was found (libnlopt-cxx-dev)
  add_fit_command(app, action);
#else
  app.add_subcommand("fit", "not built (needs NLopt: libnlopt-cxx-dev)")->allow_extras()->callback([&action] {
    action = []() -> int {
      throw ganzfeld::InputError(
          "this ganzfeld was built without NLopt, so it cannot fit; install libnlopt-cxx-dev "
          "(scripts/install-deps) and configure again");
    };
  });
#endif
  // The alias spellings of bake become its subcommands; the tables still stamp argv as typed.
  const std::vector<std::string> words = bake_alias(std::vector<std::string>(argv, argv + argc));
  std::vector<const char*> parsed;
  for (const std::string& word : words) parsed.push_back(word.c_str());
  try {
    app.parse(static_cast<int>(parsed.size()), parsed.data());
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ganzfeld: " << e.what() << " (see ganzfeld --help)\n";
    return 2;
  }
  if (parse_only) return action ? 0 : 2;
  try {
    return action ? action() : 2;
  } catch (const ganzfeld::InputError& e) {
    std::cerr << "ganzfeld: " << e.worded(ganzfeld::InputError::flag_spelling) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ganzfeld: internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace ganzfeld::cli
