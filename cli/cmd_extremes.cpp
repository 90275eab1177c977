// ganzfeld extremes: the extremes grid (reports/extremes.h) — every model at the ends
// of its parameters' ranges and the laws at extreme directions, judged against the independent
// reference; --markdown prints docs/reliability-extremes.md (scripts/docs --reliability).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "models/text_data.h"
#include "reports/extremes.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {

struct ExtremesArgs {
  bool json = false, markdown = false, quick = false, defaults_only = false;
  double tol = 1e-8;
  std::vector<std::string> models;
  std::string csv, keep;
};

nlohmann::ordered_json extremes_json(const std::vector<ExtremesRow>& rows, const ExtremesOptions& options,
                                     double seconds) {
  nlohmann::ordered_json doc{
      {"tolerance", options.engine_tolerance}, {"seconds", seconds}, {"models", nlohmann::ordered_json::array()}};
  for (const auto& r : rows) {
    nlohmann::ordered_json flagged = nlohmann::ordered_json::array();
    for (const ExtremesCase& c : r.flagged) flagged.push_back(extremes_case_json(c));
    doc["models"].push_back({{"model", r.model},
                             {"specs", r.specs},
                             {"refused", r.refused},
                             {"cases", r.cases},
                             {"non_finite", r.non_finite},
                             {"not_converged", r.not_converged},
                             {"dishonest", r.dishonest},
                             {"references_disagree", r.references_disagree},
                             {"reference_unresolved", r.unresolved},
                             {"seconds", r.seconds},
                             {"flagged", flagged}});
  }
  return doc;
}

/// The grid model by model, each model's row kept in DIR/MODEL.json once measured and read back
/// instead of measured again: a run cut off after hours resumes where it stopped. Returns the rows
/// and the summed wall time of the runs that measured them.
std::pair<std::vector<ExtremesRow>, double> kept_extremes_report(const ExtremesOptions& options,
                                                                 const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir))
    throw InputError("--keep '" + dir + "' is not a directory that can be made (" +
                     (error ? error.message() : std::string("a file is in the way")) +
                     "); allowed: a directory, existing or new");
  check_writable((std::filesystem::path(dir) / "model.json").string());  // before hours of work
  std::vector<ExtremesRow> rows;
  double wall_seconds = 0.0;
  for (const std::string& model : extremes_models(options)) {
    const std::string path = (std::filesystem::path(dir) / (model + ".json")).string();
    if (std::filesystem::exists(path)) {
      KeptExtremesRow kept =
          extremes_row_from_json(read_text_file(path, "kept extremes row '" + path + "'"), options, path);
      wall_seconds += kept.wall_seconds;
      rows.push_back(std::move(kept.row));
      continue;
    }
    ExtremesOptions one = options;
    one.models = {model};
    const util::Stopwatch watch;
    std::vector<ExtremesRow> measured = extremes_report(one);
    const double seconds = watch.seconds();
    for (ExtremesRow& row : measured) {  // the model's one row (its refused specs included)
      write_text_atomically(path, extremes_row_json(row, options, seconds));
      rows.push_back(std::move(row));
    }
    wall_seconds += seconds;
  }
  return {std::move(rows), wall_seconds};
}

/// The progress bar (on a terminal) and, at once, one line per dishonest or non-finite case.
std::function<void(const ExtremesCase&, std::size_t, std::size_t)> extremes_progress() {
  auto bar = util::progress_bar("extremes");
  return [bar](const ExtremesCase& c, std::size_t done, std::size_t total) {
    if (c.dishonest || !c.finite)
      std::fprintf(stderr, "\rextremes: %s: %s %s at %s: %.12g ± %.2g, reference %.12g ± %.2g\n",
                   c.finite ? "dishonest" : "non-finite", c.spec.c_str(), to_string(c.law), c.where.c_str(),
                   c.engine.value, c.engine.error, c.reference, c.reference_error);
    if (bar) bar(done, total);
  };
}

}  // namespace

void add_extremes_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("extremes",
                                 "the extremes grid: every model at its parameters' ends and extreme directions, "
                                 "the engine's estimates judged against the independent reference");
  auto args = std::make_shared<ExtremesArgs>();
  add_json_flag(*cmd, args->json);
  cmd->add_flag("--markdown", args->markdown, "print docs/reliability-extremes.md (Markdown)");
  cmd->add_flag("--quick", args->quick, "the slice ctest runs: default specs, the grid's corners");
  cmd->add_flag("--defaults-only", args->defaults_only,
                "every model at its defaults only (the whole direction grid; about ten times faster)");
  cmd->add_option("--tol", args->tol, "the engine's absolute tolerance (default 1e-8)");
  cmd->add_option("--model", args->models, "only these models (catalogue names, or 'mixture'); repeatable");
  cmd->add_option("--csv", args->csv,
                  "also write every case of the grid to FILE (CSV; with --markdown the section "
                  "links it by its file name, so put it beside the document)");
  cmd->add_option("--keep", args->keep,
                  "keep each model's cases in DIR/MODEL.json and reuse those an earlier run with the same "
                  "options measured (the whole grid runs for hours; empty DIR after changing the engine)");
  cmd->callback([&action, args] {
    action = [args] {
      validate_tolerance(args->tol);
      for (const std::string& name : args->models)
        if (name != "mixture") find_model(name);  // InputError naming the unknown model
      ExtremesOptions options;
      options.engine_tolerance = args->tol;
      options.models = args->models;
      options.quick = args->quick;
      options.defaults_only = args->defaults_only;
      options.on_case = extremes_progress();
      const util::Stopwatch watch;
      std::vector<ExtremesRow> rows;
      double seconds = 0.0;
      if (args->keep.empty()) {
        rows = extremes_report(options);
        seconds = watch.seconds();
      } else {
        std::tie(rows, seconds) = kept_extremes_report(options, args->keep);
      }
      std::vector<std::string> words{"ganzfeld", "extremes"};
      if (args->markdown) words.push_back("--markdown");
      if (args->quick) words.push_back("--quick");
      if (args->defaults_only) words.push_back("--defaults-only");
      if (args->tol != 1e-8) words.insert(words.end(), {"--tol", format_number(args->tol)});
      for (const std::string& name : args->models) words.insert(words.end(), {"--model", name});
      if (!args->csv.empty()) words.insert(words.end(), {"--csv", args->csv});
      if (!args->keep.empty()) words.insert(words.end(), {"--keep", "DIR"});
      const std::string command = shell_line(words);
      if (!args->csv.empty()) write_text_atomically(args->csv, extremes_csv(rows, command));
      if (args->markdown) {
        const std::string csv_name = args->csv.empty() ? "" : std::filesystem::path(args->csv).filename().string();
        std::cout << extremes_markdown(rows, options, command, seconds, csv_name, !args->keep.empty());
      } else if (args->json) {
        std::cout << extremes_json(rows, options, seconds).dump(2) << "\n";
      } else {
        for (const auto& r : rows)
          std::printf(
              "%-24s specs %3d cases %5d non-finite %d not-converged %d dishonest %d refs-disagree %d "
              "unresolved %d  %.1f s\n",
              r.model.c_str(), r.specs, r.cases, r.non_finite, r.not_converged, r.dishonest, r.references_disagree,
              r.unresolved, r.seconds);
      }
      return 0;  // a report: its targets are met or missed in what it prints
    };
  });
}

}  // namespace ganzfeld::cli
