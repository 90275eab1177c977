#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "bench/cubature_bench.h"
#include "bench/genz_bench.h"
#include "bench/realtime_bench.h"
#include "bench/render_bench.h"
#include "bench/shaders_bench.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {

struct BenchArgs {
  std::string what;
  bool json = false, quick = false;
  int cases = 0, repeats = 0, instances = 0;
  long long budget = 0;
  std::vector<double> tolerances;
  std::string markdown, plot, baseline;
  CLI::Option* markdown_option = nullptr;  ///< given, with or without a FILE
  std::vector<std::string> competitors;
  int size = 0, frames = 0;  ///< shaders: 0 = the defaults
  std::string platform = "auto", model, cache;
};

/// realtime, render and shaders print their section of docs/realtime.md with --markdown (no FILE):
/// scripts/doc-section writes it into the document, and the section names that command.
bool prints_section(const BenchArgs& args) { return args.markdown_option && args.markdown_option->count() > 0; }
void refuse_markdown_file(const BenchArgs& args) {
  if (prints_section(args) && !args.markdown.empty())
    throw InputError("bench " + args.what + " --markdown takes no FILE ('" + args.markdown +
                     "'): it prints its section of docs/realtime.md; pipe it into scripts/doc-section");
}
/// The stamped command of a section: the benchmark's words, piped into scripts/doc-section.
std::string section_command(const std::vector<std::string>& words, const std::string& section) {
  return shell_line(words) + " | scripts/doc-section docs/realtime.md " + section;
}

/// Bake timings are repeated (median and spread): 5 runs by default, 1 with --quick.
int bake_repeats(const BenchArgs& args) { return args.repeats > 0 ? args.repeats : (args.quick ? 1 : 5); }

nlohmann::ordered_json cubature_report(const BenchArgs& args) {
  if (prints_section(args) && args.markdown.empty())
    throw InputError("bench cubature --markdown needs the FILE to write (docs/performance.md)");
  bench::CubatureBenchOptions options = args.quick ? bench::quick_options() : bench::CubatureBenchOptions{};
  if (args.cases > 0) options.cases_per_family = args.cases;
  for (const std::string& who : args.competitors)
    if (std::find(bench::cubature_competitors().begin(), bench::cubature_competitors().end(), who) ==
        bench::cubature_competitors().end()) {
      std::string allowed;
      for (const std::string& name : bench::cubature_competitors()) allowed += (allowed.empty() ? "" : ", ") + name;
      throw InputError("unknown competitor '" + who + "'; allowed: " + allowed);
    }
  options.competitors = args.competitors;
  if (!args.markdown.empty() && !args.competitors.empty())
    throw InputError("--markdown writes the whole report; drop --competitors or --markdown");
  // Read before the run: a bad file is refused at once, not after minutes of benchmark.
  const std::optional<bench::EvaluationBaseline> baseline =
      args.baseline.empty() ? std::nullopt : std::optional(bench::read_evaluation_baseline(args.baseline));
  const auto families = bench::run_cubature_benchmark(options);
  // The report includes the bake throughput, measured in the same run (no appended sections).
  const std::vector<bench::BakeTiming> bakes = args.markdown.empty()
                                                   ? std::vector<bench::BakeTiming>{}
                                                   : bench::run_bake_benchmark(args.quick, bake_repeats(args));
  if (!args.plot.empty()) bench::write_work_precision_plot(families, args.plot);
  if (!args.markdown.empty()) {
    std::vector<std::string> words{"ganzfeld", "bench", "cubature"};
    if (args.quick) words.push_back("--quick");
    if (args.cases > 0) words.insert(words.end(), {"--cases", std::to_string(args.cases)});
    if (args.repeats > 0) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
    words.insert(words.end(), {"--markdown", args.markdown});
    if (!args.plot.empty()) words.insert(words.end(), {"--plot", args.plot});
    if (!args.baseline.empty()) words.insert(words.end(), {"--baseline", args.baseline});
    const std::string command = shell_line(words);
    const std::string plot_file = args.plot.empty() ? "" : std::filesystem::path(args.plot).filename().string();
    write_text_atomically(args.markdown, bench::performance_markdown(families, options, bakes, command, plot_file,
                                                                     baseline ? &*baseline : nullptr));
  }
  nlohmann::ordered_json doc;
  doc["benchmark"] = "cubature";
  doc["ratio_tolerance"] = options.ratio_tolerance;
  doc["tolerances"] = options.tolerances;
  doc["competitor_cap"] = options.competitor_cap;
  doc["families"] = nlohmann::ordered_json::array();
  for (const auto& f : families) {
    nlohmann::ordered_json ratios, capped;
    for (const auto& [who, r] : f.evals_ratio) ratios[who] = r;
    for (const auto& [who, n] : f.capped) capped[who] = n;
    nlohmann::ordered_json misses = nlohmann::ordered_json::array();
    for (const auto& m : f.misses)
      misses.push_back({{"model", m.model},
                        {"i", m.i},
                        {"j", m.j},
                        {"tolerance", m.tolerance},
                        {"achieved_error", m.achieved_error},
                        {"estimate", m.estimate},
                        {"resolution", m.resolution},
                        {"evaluations", m.evaluations}});
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (const auto& r : f.runs)
      runs.push_back({r.competitor, r.tolerance, r.achieved_error, r.evaluations, r.seconds, r.capped, r.claimed});
    nlohmann::ordered_json failures;
    for (const auto& [who, x] : f.failures)
      failures[who] = {{"runs", x.runs},
                       {"silently_wrong", x.silently_wrong},
                       {"not_converged", x.not_converged},
                       {"over_cap", x.over_cap},
                       {"missed", x.missed},
                       {"dishonest", x.dishonest}};
    nlohmann::ordered_json disagreements = nlohmann::ordered_json::array();
    for (const auto& d : f.disagreements)
      disagreements.push_back({{"model", d.model},
                               {"i", d.i},
                               {"j", d.j},
                               {"boost_reference", d.boost_reference},
                               {"ours_reference", d.ours_reference}});
    doc["families"].push_back(
        {{"name", f.name},
         {"cases", f.cases},
         {"skipped", f.skipped},
         {"missed_rate", f.missed_rate},
         {"dishonest_rate", f.dishonest_rate},
         {"evals_ratio", ratios},
         {"capped_cases", capped},
         {"mc_error_ratio_equal_time", f.mc_error_ratio_equal_time},
         {"failures", failures},
         {"reference_disagreements", disagreements},
         {"runs_columns", {"competitor", "tolerance", "achieved_error", "evaluations", "seconds", "capped", "claimed"}},
         {"runs", runs},
         {"misses", misses}});
  }
  return doc;
}

/// Bake throughput: a 64x64x32 g table at 1e-9 for specular alpha = 8 and 1000, with
/// 1 and 2 threads, repeated (bench/bake_bench.cpp).
nlohmann::ordered_json bake_report(const BenchArgs& args) {
  nlohmann::ordered_json doc{{"benchmark", "bake"}, {"machine", util::machine_description()}};
  doc["tables"] = nlohmann::ordered_json::array();
  for (const bench::BakeTiming& b : bench::run_bake_benchmark(args.quick, bake_repeats(args))) {
    const double one = util::median(b.seconds_1), two = util::median(b.seconds_2);
    doc["tables"].push_back({{"model", b.model},
                             {"law", "g"},
                             {"resolution", b.resolution},
                             {"tolerance", 1e-9},
                             {"unconverged", b.unconverged},
                             {"max_error", b.max_error},
                             {"seconds_1_thread_runs", b.seconds_1},
                             {"seconds_2_threads_runs", b.seconds_2},
                             {"seconds_1_thread", one},
                             {"seconds_2_threads", two},
                             {"speedup_2_threads", one / two}});
  }
  return doc;
}

/// The render benchmark (bench/render_bench.h): --repeats side-by-side runs (default 7, quick 1).
int render_report(const BenchArgs& args) {
  refuse_markdown_file(args);
  const int repeats = args.repeats > 0 ? args.repeats : (args.quick ? 1 : 7);
  const auto r = bench::run_render_benchmark(args.quick, repeats);
  if (prints_section(args)) {
    std::vector<std::string> words{"ganzfeld", "bench", "render"};
    if (args.quick) words.push_back("--quick");
    if (args.repeats > 0) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
    words.push_back("--markdown");
    std::cout << bench::render_markdown(r, section_command(words, "render"));
    return 0;
  }
  auto runs = [](const std::vector<double>& v) {
    return nlohmann::ordered_json{{"median", util::median(v)},
                                  {"min", *std::min_element(v.begin(), v.end())},
                                  {"max", *std::max_element(v.begin(), v.end())},
                                  {"runs", v}};
  };
  const nlohmann::ordered_json doc{
      {"benchmark", "render"},
      {"size", r.size},
      {"direct_crop", r.crop},
      {"repeats", r.repeats},
      {"seconds",
       {{"lambert_ambient", runs(r.seconds_lambert)},
        {"tables", runs(r.seconds_tables)},
        {"direct_crop", runs(r.seconds_direct)}}},
      {"ratios", {{"tables_vs_lambert", runs(r.tables_vs_lambert)}, {"direct_vs_tables", runs(r.direct_vs_tables)}}}};
  if (args.json) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf(
      "%dx%d sphere, %d runs: Lambert + ambient %.3f s, tables (3 lights, 2 lobes) %.3f s, direct %dx%d crop %.3f s "
      "(medians)\nper pixel: tables / Lambert = %.2f (%.2f … %.2f), direct / tables = %.3g\n",
      r.size, r.size, r.repeats, util::median(r.seconds_lambert), util::median(r.seconds_tables), r.crop, r.crop,
      util::median(r.seconds_direct), util::median(r.tables_vs_lambert),
      *std::min_element(r.tables_vs_lambert.begin(), r.tables_vs_lambert.end()),
      *std::max_element(r.tables_vs_lambert.begin(), r.tables_vs_lambert.end()), util::median(r.direct_vs_tables));
  return 0;
}

/// Genz's test families (bench/genz_bench.h): a summary per family and competitor, or with
/// `--markdown -` docs/reliability-genz.md on stdout.
int genz_report(const BenchArgs& args) {
  bench::GenzOptions options = args.quick ? bench::quick_genz_options() : bench::GenzOptions{};
  if (args.instances != 0) options.instances = args.instances;
  if (args.budget != 0) options.budget = args.budget;
  if (!args.tolerances.empty()) options.tolerances = args.tolerances;
  bench::check_genz_options(options);
  if (prints_section(args) && args.markdown != "-")
    throw InputError("bench genz --markdown takes '-'" +
                     (args.markdown.empty() ? "" : ", not '" + args.markdown + "'") +
                     " (docs/reliability-genz.md on stdout)");
  const util::Stopwatch watch;
  const auto cells = bench::run_genz_benchmark(options);
  const double seconds = watch.seconds();
  if (!args.markdown.empty()) {
    std::vector<std::string> words{"ganzfeld", "bench", "genz"};
    if (args.quick) words.push_back("--quick");
    if (args.instances != 0) words.insert(words.end(), {"--instances", std::to_string(args.instances)});
    if (args.budget != 0) words.insert(words.end(), {"--budget", std::to_string(args.budget)});
    if (!args.tolerances.empty()) {
      std::string list;
      for (double t : args.tolerances) list += (list.empty() ? "" : ",") + format_number(t);
      words.insert(words.end(), {"--tolerances", list});
    }
    words.insert(words.end(), {"--markdown", "-"});
    std::cout << bench::genz_markdown(cells, options, shell_line(words), seconds);
    return 0;
  }
  if (args.json) {
    nlohmann::ordered_json doc{{"benchmark", "genz"},
                               {"instances", options.instances},
                               {"budget", options.budget},
                               {"tolerances", options.tolerances},
                               {"cells", nlohmann::ordered_json::array()}};
    for (const auto& c : cells)
      doc["cells"].push_back({{"family", bench::to_string(c.family)},
                              {"dimension", c.dimension},
                              {"competitor", c.competitor},
                              {"runs", c.runs},
                              {"dishonest", c.dishonest},
                              {"dishonest_unseen", c.dishonest_unseen},
                              {"worst_ratio", c.worst_ratio},
                              {"not_converged", c.not_converged},
                              {"capped", c.capped},
                              {"evaluations", c.evaluations},
                              {"geometric_mean_evaluations", c.geometric_mean_evaluations()}});
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("%-14s %2s %-20s %6s %9s %9s %10s %9s %9s %12s\n", "family", "n", "competitor", "runs", "dishonest",
              "unseen", "worst", "not-conv", "capped", "geo-evals");
  for (const auto& c : cells)
    std::printf("%-14s %2d %-20s %6d %9d %9d %10.3g %9d %9d %12.4g\n", bench::to_string(c.family), c.dimension,
                c.competitor.c_str(), c.runs, c.dishonest, c.dishonest_unseen, c.worst_ratio, c.not_converged, c.capped,
                c.geometric_mean_evaluations());
  return 0;
}

/// The shaders benchmark (bench/shaders_bench.h): its section of docs/realtime.md with --markdown,
/// JSON with --json, else a table.
int shaders_report(const BenchArgs& args) {
  refuse_markdown_file(args);
  bench::ShadersBenchOptions options = args.quick ? bench::quick_shaders_options() : bench::ShadersBenchOptions{};
  if (args.size > 0) options.size = args.size;
  if (args.frames > 0) options.frames = args.frames;
  options.platform = gl::parse_platform(args.platform);
  if (!args.model.empty()) options.model = args.model;
  options.cache_dir = args.cache;
  const bench::ShadersBenchResult r = bench::run_shaders_benchmark(options);
  if (prints_section(args)) {
    std::vector<std::string> words{"ganzfeld", "bench", "shaders"};
    if (args.quick) words.push_back("--quick");
    if (args.size > 0) words.insert(words.end(), {"--size", std::to_string(args.size)});
    if (args.frames > 0) words.insert(words.end(), {"--frames", std::to_string(args.frames)});
    if (args.platform != "auto") words.insert(words.end(), {"--platform", args.platform});
    if (!args.model.empty()) words.insert(words.end(), {"--model", args.model});
    if (!args.cache.empty()) words.insert(words.end(), {"--cache", args.cache});
    words.push_back("--markdown");
    std::cout << bench::shaders_markdown(r, section_command(words, bench::shaders_section(r)));
    return 0;
  }
  const double a = util::median(r.passes.at(0).milliseconds), s = util::median(r.passes.at(1).milliseconds);
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (const bench::ShaderPass& p : r.passes) {
    nlohmann::ordered_json laws = nlohmann::ordered_json::array();
    for (const bench::LawLookup& l : p.laws)
      laws.push_back({{"law", to_string(l.law)},
                      {"scheme", l.scheme},
                      {"lookup_error", l.lookup_error},
                      {"value_bytes", l.value_bytes},
                      {"fetches", l.fetches_max},
                      {"points", l.points},
                      {"max_difference", l.max_difference}});
    const double m = util::median(p.milliseconds);
    passes.push_back({{"name", p.name},
                      {"what", p.what},
                      {"table_set", p.table_set},
                      {"define", p.define},
                      {"milliseconds",
                       {{"median", m},
                        {"min", *std::min_element(p.milliseconds.begin(), p.milliseconds.end())},
                        {"max", *std::max_element(p.milliseconds.begin(), p.milliseconds.end())}}},
                      {"vs_a", m / a},
                      {"vs_s", m / s},
                      {"fetches_per_pixel", p.fetches_mean},
                      {"fetches_per_pixel_max", p.fetches_max},
                      {"value_bytes", p.value_bytes},
                      {"laws", laws}});
  }
  const nlohmann::ordered_json doc{{"benchmark", "shaders"},
                                   {"gl_renderer", r.context.gl_renderer},
                                   {"gl_version", r.context.gl_version},
                                   {"gl_vendor", r.context.gl_vendor},
                                   {"platform", r.context.platform},
                                   {"software", r.context.software},
                                   {"timer", r.timer},
                                   {"size", r.size},
                                   {"frames", r.frames},
                                   {"points", r.points},
                                   {"passes", passes}};
  if (args.json) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("GL_RENDERER %s | GL_VERSION %s | %s (%s); %dx%d, %d frames, %s\n", r.context.gl_renderer.c_str(),
              r.context.gl_version.c_str(), r.context.gl_vendor.c_str(), r.context.platform.c_str(), r.size, r.size,
              r.frames, r.timer.c_str());
  for (const auto& p : doc["passes"])
    std::printf("%-32s %9.3f ms  %6.2f x A  %6.2f x S  %6.1f fetches  %9llu bytes\n",
                (p["name"].get<std::string>()).c_str(), p["milliseconds"]["median"].get<double>(),
                p["vs_a"].get<double>(), p["vs_s"].get<double>(), p["fetches_per_pixel"].get<double>(),
                static_cast<unsigned long long>(p["value_bytes"].get<std::uint64_t>()));
  return 0;
}

/// The real-time tables' accuracy report: its section of docs/realtime.md, printed.
int realtime_report(const BenchArgs& args) {
  refuse_markdown_file(args);
  std::vector<std::string> words{"ganzfeld", "bench", "realtime"};
  if (args.quick) words.push_back("--quick");
  if (args.repeats > 0) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
  words.push_back("--markdown");
  bench::RealtimeOptions options;
  options.quick = args.quick;
  options.repeats = bake_repeats(args);
  std::cout << bench::realtime_markdown(options, section_command(words, "realtime"));
  return 0;
}

}  // namespace

void add_bench_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("bench", "benchmarks that print ratios measured in one run");
  auto args = std::make_shared<BenchArgs>();
  cmd->add_option("what", args->what, "cubature | genz | bake | render | realtime | shaders")->required();
  add_json_flag(*cmd, args->json);
  cmd->add_flag("--quick", args->quick, "a small sample (CI); the full run takes minutes");
  cmd->add_option("--cases", args->cases, "cases per integrand family (cubature; default 200, quick 4)");
  cmd->add_option("--repeats", args->repeats,
                  "runs of each bake timing (default 5, quick 1), or of the render benchmark (default 7, quick 1); "
                  "medians and spread");
  args->markdown_option = cmd->add_option("--markdown", args->markdown,
                                          "cubature: also write the report (docs/performance.md) to FILE; realtime, "
                                          "render, shaders: print the section of docs/realtime.md (no FILE); "
                                          "genz: '-' prints docs/reliability-genz.md")
                              ->expected(0, 1);
  cmd->add_option("--instances", args->instances,
                  "genz: random instances per family and dimension (default 500, quick 3)");
  cmd->add_option("--budget", args->budget, "genz: evaluations per competitor run (default 1000000)");
  cmd->add_option("--tolerances", args->tolerances,
                  "genz: relative tolerances, comma-separated (default 1e-3 ... 1e-12)")
      ->delimiter(',');
  cmd->add_option("--size", args->size, "shaders: the pass's width and height in pixels (default 2048, quick 128)");
  cmd->add_option("--frames", args->frames, "shaders: timed frames per pass (default 30)");
  cmd->add_option("--platform", args->platform,
                  "shaders: EGL platform: auto (a GPU's device, else Mesa surfaceless), device, surfaceless");
  cmd->add_option("--model", args->model, "shaders: the glossy lobe shaded from tables (default specular:alpha=100)");
  cmd->add_option("--cache", args->cache, "shaders: keep the tables in this cache directory between runs");
  cmd->add_option("--plot", args->plot, "cubature: also write the work-precision plot (PNG) to FILE");
  cmd->add_option("--competitors", args->competitors,
                  "cubature: only these competitors, comma-separated (ours, ours_no_hints, oracle, mc, hcubature_lune, "
                  "hcubature_naive, pcubature_lune, boost_gauss_kronrod, boost_tanh_sinh; default all)")
      ->delimiter(',');
  cmd->add_option("--baseline", args->baseline,
                  "cubature: compare our evaluations per family with FILE (scripts/performance-baseline)");
  cmd->callback([&action, args] {
    action = [args] {
      if (args->what == "realtime") return realtime_report(*args);
      if (args->what == "render") return render_report(*args);
      if (args->what == "shaders") return shaders_report(*args);
      if (args->what == "genz") return genz_report(*args);
      nlohmann::ordered_json doc;
      if (args->what == "cubature") doc = cubature_report(*args);
      else if (args->what == "bake") doc = bake_report(*args);
      else
        throw InputError("unknown benchmark '" + args->what +
                         "'; allowed: cubature, genz, bake, render, realtime, shaders");
      if (args->json) {
        std::cout << doc.dump(2) << "\n";
        return 0;
      }
      if (args->what == "cubature") {
        std::printf("evaluations of each competitor / ours to reach error %.0e (geometric mean; > = capped cases)\n",
                    doc["ratio_tolerance"].get<double>());
        std::printf("%-20s %5s %7s %8s %9s %9s %9s %9s %9s %9s %9s\n", "family", "cases", "missed", "oracle",
                    "hcub_lune", "hcub_naive", "pcub_lune", "boost_gk", "boost_ts", "mc_err", "dishonest");
        for (const auto& f : doc["families"]) {
          auto ratio = [&](const char* who) { return f["evals_ratio"].value(who, 0.0); };
          std::printf("%-20s %5d %7.4f %8.3g %9.3g %9.3g %9.3g %9.3g %9.3g %9.2g %9.4f\n",
                      f["name"].get<std::string>().c_str(), f["cases"].get<int>(), f["missed_rate"].get<double>(),
                      ratio("oracle"), ratio("hcubature_lune"), ratio("hcubature_naive"), ratio("pcubature_lune"),
                      ratio("boost_gauss_kronrod"), ratio("boost_tanh_sinh"),
                      f["mc_error_ratio_equal_time"].get<double>(), f["dishonest_rate"].get<double>());
        }
      } else {
        for (const auto& t : doc["tables"])
          std::printf(
              "%-22s g %s tol 1e-9: median %.2f s (1 thread), %.2f s (2 threads), speed-up %.2f, unconverged %lld\n",
              t["model"].get<std::string>().c_str(), t["resolution"].dump().c_str(),
              t["seconds_1_thread"].get<double>(), t["seconds_2_threads"].get<double>(),
              t["speedup_2_threads"].get<double>(), t["unconverged"].get<long long>());
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
