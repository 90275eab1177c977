// Each sub-command registers its options and returns the action to run after parsing.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ganzfeld::cli {

/// The action of the selected sub-command; returns the process exit code.
using Action = std::function<int()>;

void add_models_command(CLI::App& app, Action& action);
void add_eval_command(CLI::App& app, Action& action);
void add_verify_command(CLI::App& app, Action& action);
void add_bake_command(CLI::App& app, Action& action, int argc,
                      const char* const* argv);  ///< argv: the command metadata
/// The command line with the alias spellings of bake (`bake --model ...`, `bake --preset ...`,
/// `bake --scene ...`, `bake --library ...`) given their job's subcommand (`bake model --model
/// ...`); the old dispatch order decides: --preset, then --scene, --library, --model. Other words
/// are returned as they are.
std::vector<std::string> bake_alias(const std::vector<std::string>& words);
void add_info_command(CLI::App& app, Action& action);
void add_sample_command(CLI::App& app, Action& action);
void add_tradeoff_command(CLI::App& app, Action& action);
void add_bench_command(CLI::App& app, Action& action);
void add_render_command(CLI::App& app, Action& action);
void add_figure_command(CLI::App& app, Action& action);
void add_export_glsl_command(CLI::App& app, Action& action);
void add_export_brdf_command(CLI::App& app, Action& action);
void add_plausibility_command(CLI::App& app, Action& action);
void add_serve_command(CLI::App& app, Action& action);
void add_extremes_command(CLI::App& app, Action& action);
void add_fit_command(CLI::App& app, Action& action);

}  // namespace ganzfeld::cli
