// `ganzfeld tradeoff`: the speed/accuracy trade of a law's tables, measured in one run against a
// dense cubature reference (reports/tradeoff.h says what is measured and how).
#include <unistd.h>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "models/spec.h"
#include "reports/schemes.h"
#include "reports/tradeoff.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"

namespace ganzfeld::cli {

namespace {

struct TradeoffArgs {
  std::string model, law, plot, markdown, resolutions, mappings;
  bool json = false, quick = false, schemes = false, one_fetch = false;
  long long points = -1;  // -1: 2000, or 300 with --quick
  long long seed = 1;
  int repeats = 3;  // --schemes: bake runs per row
};

constexpr long long kDefaultPoints = 2000;
constexpr long long kQuickPoints = 300;
constexpr long long kMaxPoints = 1'000'000;

/// The sweep, narrowed by --res / --mapping when given ("N,N,..." / "M[xMxM],...").
reports::TradeoffPlan make_plan(Law law, const TradeoffArgs& args) {
  reports::TradeoffPlan plan = args.quick ? reports::quick_plan(law) : reports::full_plan(law);
  auto split = [](const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
      const std::size_t c = text.find(',', start);
      parts.push_back(text.substr(start, c == std::string::npos ? std::string::npos : c - start));
      if (c == std::string::npos) break;
      start = c + 1;
    }
    return parts;
  };
  if (!args.resolutions.empty()) {
    plan.resolutions.clear();
    for (const std::string& r : split(args.resolutions)) plan.resolutions.push_back(tables::parse_resolution(r, law));
  }
  if (!args.mappings.empty()) {
    plan.mapping_sets.clear();
    for (const std::string& m : split(args.mappings)) {
      std::vector<tables::Mapping> set = tables::parse_mappings(m, law);
      if (set.empty())  // "default"
        for (const tables::Axis& axis : tables::default_axes(law, plan.resolutions.front()))
          set.push_back(axis.mapping);
      plan.mapping_sets.push_back(set);
    }
  }
  return plan;
}

/// The command that reproduces the measurement (outputs omitted), with the model in canonical form.
std::string measurement_command(const TradeoffArgs& args, const std::string& spec, Law law) {
  std::vector<std::string> words{"ganzfeld", "tradeoff", "--model", spec, "--law", to_string(law)};
  if (args.schemes) words.push_back("--schemes");
  if (args.schemes && args.repeats != 3) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
  if (args.quick) words.push_back("--quick");
  if (args.one_fetch) words.push_back("--one-fetch");
  if (args.points >= 0) words.insert(words.end(), {"--points", std::to_string(args.points)});
  if (args.seed != 1) words.insert(words.end(), {"--seed", std::to_string(args.seed)});
  if (!args.resolutions.empty()) words.insert(words.end(), {"--res", args.resolutions});
  if (!args.mappings.empty()) words.insert(words.end(), {"--mapping", args.mappings});
  return shell_line(words);
}

nlohmann::ordered_json to_json(const reports::TradeoffReport& report, bool quick, const std::string& command) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const reports::TradeoffRow& r : report.rows) {
    nlohmann::ordered_json mappings = nlohmann::ordered_json::array();
    for (tables::Mapping m : r.config.mappings) mappings.push_back(to_string(m));
    rows.push_back(
        {{"resolution", r.config.resolution},
         {"mappings", mappings},
         {"encoding", to_string(r.config.encoding)},
         {"tolerance", r.config.tolerance},
         {"entries", r.entries},
         {"bytes", r.bytes},
         {"texture_bytes", r.texture_bytes},
         {"file_bytes", r.file_bytes},
         {"bake_seconds", r.bake_seconds},
         {"lookup_ns", r.lookup_ns},
         {"max_error", r.max_error},
         {"rms_error", r.rms_error},
         {"max_stored_error", r.max_stored_error},
         {"unconverged", r.unconverged},
         {"worst", {{"i", {r.worst.i.x, r.worst.i.y, r.worst.i.z}}, {"j", {r.worst.j.x, r.worst.j.y, r.worst.j.z}}}}});
  }
  const reports::Reference& ref = report.reference;
  return {{"model", report.model},
          {"law", to_string(report.law)},
          {"quick", quick},
          {"command", command},
          {"reference",
           {{"points", ref.points.size()},
            {"extreme_points", ref.extreme_points},
            {"seed", ref.seed},
            {"tolerance", ref.tolerance},
            {"max_error", ref.max_error},
            {"unconverged", ref.unconverged},
            {"seconds", ref.seconds}}},
          {"seconds", report.seconds},
          {"rows", rows}};
}

nlohmann::ordered_json schemes_json(const reports::SchemeReport& report, const std::string& command) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const reports::SchemeRow& r : report.rows) {
    const reports::Spread t = reports::bake_spread(r);
    nlohmann::ordered_json row{{"kind", to_string(r.kind)}, {"label", reports::scheme_label(r)}};
    if (r.kind == reports::SchemeKind::max_error)  // encoding here too: refused rows name what was asked
      row.update({{"target", r.target},
                  {"target_bytes", r.target_bytes},
                  {"target_fetches", r.target_fetches},
                  {"encoding", to_string(r.encoding)}});
    if (!r.refused.empty()) {
      row["refused"] = r.refused;
    } else {
      row.update({{"frame", to_string(r.frame)},
                  {"interpolation", to_string(r.interpolation)},
                  {"encoding", to_string(r.encoding)},
                  {"resolution", r.resolution},
                  {"value_bytes", r.value_bytes},
                  {"bake_seconds", r.bake_seconds},
                  {"bake_median", t.median},
                  {"bake_min", t.min},
                  {"bake_max", t.max},
                  {"max_error", r.max_error},
                  {"rms_error", r.rms_error},
                  {"lookup_error", r.lookup_error},
                  {"covered", r.covered},
                  {"fetches", r.fetches},
                  {"filter", to_string(r.filter)}});
    }
    rows.push_back(row);
  }
  const reports::Reference& ref = report.reference;
  return {{"model", report.model},
          {"law", to_string(report.law)},
          {"command", command},
          {"reference",
           {{"points", ref.points.size()},
            {"seed", ref.seed},
            {"tolerance", ref.tolerance},
            {"min_cos", reports::kSchemeMinCos},
            {"max_error", ref.max_error},
            {"unconverged", ref.unconverged},
            {"seconds", ref.seconds}}},
          {"repeats", report.repeats},
          {"seconds", report.seconds},
          {"rows", rows}};
}

/// --plot's file name as the Markdown links it (beside the Markdown).
std::string plot_link(const std::string& plot) {
  const std::size_t slash = plot.find_last_of('/');
  return slash == std::string::npos ? plot : plot.substr(slash + 1);
}

/// `tradeoff --schemes`: reports/schemes.h.
int run_schemes(const TradeoffArgs& args, const Model& model, Law law, long long points) {
  reports::SchemeOptions options;
  options.points = static_cast<int>(points);
  options.seed = static_cast<std::uint64_t>(args.seed);
  options.repeats = args.repeats;
  options.quick = args.quick;
  options.one_fetch_only = args.one_fetch;
  if (auto bar = util::progress_bar("tradeoff: schemes"))
    options.progress = [bar](std::size_t done, std::size_t total) { bar(done, total); };
  const reports::SchemeReport report = reports::measure_schemes(model, law, options);
  const std::string command = measurement_command(args, model.spec(), law);
  if (!args.plot.empty()) reports::write_schemes_plot(report, args.plot);
  if (!args.markdown.empty())
    write_text_atomically(args.markdown,
                          reports::schemes_markdown(report, command, args.plot.empty() ? "" : plot_link(args.plot)));
  if (args.json) {
    std::cout << schemes_json(report, command).dump(2) << "\n";
  } else {
    for (const reports::SchemeRow& r : report.rows)
      std::printf("%-36s %s\n", reports::scheme_label(r).c_str(),
                  r.refused.empty()
                      ? (std::to_string(r.value_bytes) + " B, max error " + format_number(r.max_error)).c_str()
                      : r.refused.c_str());
  }
  return 0;
}

void print_text(const reports::TradeoffReport& report) {
  std::printf("%s law %s: %zu reference points (tolerance %.0e), %.1f s\n", report.model.c_str(), to_string(report.law),
              report.reference.points.size(), report.reference.tolerance, report.seconds);
  std::printf("%-10s %-16s %-5s %-6s %10s %10s %9s %8s %10s %10s %10s\n", "res", "mappings", "enc", "tol", "bytes",
              "file", "bake s", "ns/look", "max err", "rms err", "stored");
  for (const reports::TradeoffRow& r : report.rows)
    std::printf("%-10s %-16s %-5s %-6.0e %10llu %10llu %9.4f %8.1f %10.3g %10.3g %10.3g\n",
                tables::resolution_text(r.config.resolution).c_str(), reports::mappings_text(r.config.mappings).c_str(),
                to_string(r.config.encoding), r.config.tolerance, static_cast<unsigned long long>(r.bytes),
                static_cast<unsigned long long>(r.file_bytes), r.bake_seconds, r.lookup_ns, r.max_error, r.rms_error,
                r.max_stored_error);
}

}  // namespace

void add_tradeoff_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "tradeoff",
      "measure table error, bytes, bake and lookup time over resolutions x mappings x encodings x tolerances");
  auto args = std::make_shared<TradeoffArgs>();
  add_model_option(*cmd, args->model);
  cmd->add_option("--law", args->law, "g (vignetting), h (darkening) or a (albedo)")->required();
  add_json_flag(*cmd, args->json);
  cmd->add_option("--plot", args->plot, "write a PNG: max error vs bytes and vs bake time");
  cmd->add_option("--markdown", args->markdown, "write the summary and the table as Markdown");
  cmd->add_flag("--quick", args->quick, "a few configurations and 300 points (seconds; for tests and CI)");
  cmd->add_option("--points", args->points, "random reference points (default 2000, 300 with --quick)");
  cmd->add_option("--seed", args->seed, "seed of the random reference points (default 1)");
  cmd->add_option("--res", args->resolutions, "only these resolutions, comma-separated, e.g. 17x17x9,33x33x17");
  cmd->add_flag("--schemes", args->schemes,
                "instead of the sweep: today's scheme vs format version 2's, what --max-error picks, linear vs "
                "cubic, half vs float (reports/schemes.h)");
  cmd->add_option("--repeats", args->repeats,
                  "with --schemes: bake runs per row, for the median and spread (default 3)");
  cmd->add_flag(
      "--one-fetch", args->one_fetch,
      "with --schemes: only the fetch-budget rows (warped frame, hardware filter; the b-spline; --max-error 1e-3 "
      "--fetches 1 and --max-error 1e-4 --max-bytes 256000 --fetches 8)");
  cmd->add_option("--mapping", args->mappings,
                  "only these mapping sets, comma-separated, each default or M[xMxM] with M = linear, sqrt, cos");
  cmd->callback([&action, args] {
    action = [args] {
      const Law law = tables::parse_tabulated_law("--law", args->law);
      const ModelPtr model = parse_model(args->model);
      const long long points = args->points < 0 ? (args->quick ? kQuickPoints : kDefaultPoints) : args->points;
      if (points < 1 || points > kMaxPoints)
        throw InputError("--points=" + std::to_string(args->points) + " is not allowed; expected an integer in [1, " +
                         std::to_string(kMaxPoints) + "]");
      if (args->seed < 0)
        throw InputError("--seed=" + std::to_string(args->seed) + " is not allowed; expected an integer >= 0");
      // Refuse unwritable outputs before the measurement, not after.
      if (!args->plot.empty()) check_writable(args->plot);
      if (!args->markdown.empty()) check_writable(args->markdown);
      if (!args->schemes && args->repeats != 3)
        throw InputError("--repeats needs --schemes (the sweep bakes once per row)");
      if (!args->schemes && args->one_fetch) throw InputError("--one-fetch needs --schemes");
      if (args->schemes) {
        if (!args->resolutions.empty() || !args->mappings.empty())
          throw InputError("--res and --mapping narrow the sweep; --schemes measures fixed schemes (drop them)");
        return run_schemes(*args, *model, law, points);
      }
      const reports::TradeoffPlan plan = make_plan(law, *args);

      reports::TradeoffOptions options;
      options.points = static_cast<int>(points);
      options.seed = static_cast<std::uint64_t>(args->seed);
      if (auto bar = util::progress_bar("tradeoff: configurations"))
        options.progress = [bar](std::size_t done, std::size_t total) { bar(done, total); };
      const reports::TradeoffReport report = reports::measure_tradeoff(*model, law, plan, options);
      const std::string command = measurement_command(*args, model->spec(), law);

      if (!args->plot.empty()) reports::write_tradeoff_plot(report, args->plot);
      if (!args->markdown.empty())
        write_text_atomically(args->markdown, reports::tradeoff_markdown(
                                                  report, command, args->plot.empty() ? "" : plot_link(args->plot)));
      if (args->json) std::cout << to_json(report, args->quick, command).dump(2) << "\n";
      else print_text(report);
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
