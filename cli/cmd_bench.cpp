#include <filesystem>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "bench/cubature_bench.h"
#include "bench/realtime_bench.h"
#include "bench/render_bench.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "util/error.h"
#include "models/spec.h"
#include "util/atomic_file.h"
#include "tables/bake.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {

struct BenchArgs {
  std::string what;
  bool json = false, quick = false;
  int cases = 0, repeats = 0;
  std::string markdown, plot;
};

/// Bake timings are repeated (median and spread): 5 runs by default, 1 with --quick.
int bake_repeats(const BenchArgs& args) { return args.repeats > 0 ? args.repeats : (args.quick ? 1 : 5); }

nlohmann::ordered_json cubature_report(const BenchArgs& args) {
  bench::CubatureBenchOptions options = args.quick ? bench::quick_options() : bench::CubatureBenchOptions{};
  if (args.cases > 0) options.cases_per_family = args.cases;
  const auto families = bench::run_cubature_benchmark(options);
  // The report includes the bake throughput, measured in the same run (no appended sections).
  const std::vector<bench::BakeTiming> bakes =
      args.markdown.empty() ? std::vector<bench::BakeTiming>{} : bench::run_bake_benchmark(args.quick, bake_repeats(args));
  if (!args.plot.empty()) bench::write_work_precision_plot(families, args.plot);
  if (!args.markdown.empty()) {
    std::vector<std::string> words{"ganzfeld", "bench", "cubature"};
    if (args.quick) words.push_back("--quick");
    if (args.cases > 0) words.insert(words.end(), {"--cases", std::to_string(args.cases)});
    if (args.repeats > 0) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
    words.insert(words.end(), {"--markdown", args.markdown});
    if (!args.plot.empty()) words.insert(words.end(), {"--plot", args.plot});
    const std::string command = shell_line(words);
    const std::string plot_file = args.plot.empty() ? "" : std::filesystem::path(args.plot).filename().string();
    write_text_atomically(args.markdown, bench::performance_markdown(families, options, bakes, command, plot_file));
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
      misses.push_back({{"model", m.model}, {"i", m.i}, {"j", m.j}, {"tolerance", m.tolerance},
                        {"achieved_error", m.achieved_error}, {"estimate", m.estimate}, {"resolution", m.resolution},
                        {"evaluations", m.evaluations}});
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (const auto& r : f.runs)
      runs.push_back({r.competitor, r.tolerance, r.achieved_error, r.evaluations, r.seconds, r.capped, r.claimed});
    nlohmann::ordered_json failures;
    for (const auto& [who, x] : f.failures)
      failures[who] = {{"runs", x.runs}, {"silently_wrong", x.silently_wrong}, {"not_converged", x.not_converged},
                       {"over_cap", x.over_cap}, {"missed", x.missed}, {"dishonest", x.dishonest}};
    nlohmann::ordered_json disagreements = nlohmann::ordered_json::array();
    for (const auto& d : f.disagreements)
      disagreements.push_back({{"model", d.model}, {"i", d.i}, {"j", d.j}, {"boost_reference", d.boost_reference},
                               {"ours_reference", d.ours_reference}});
    doc["families"].push_back({{"name", f.name},
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
  nlohmann::ordered_json doc{{"benchmark", "bake"}, {"machine", bench::machine_description()}};
  doc["tables"] = nlohmann::ordered_json::array();
  for (const bench::BakeTiming& b : bench::run_bake_benchmark(args.quick, bake_repeats(args))) {
    const double one = util::median(b.seconds_1), two = util::median(b.seconds_2);
    doc["tables"].push_back({{"model", b.model}, {"law", "g"}, {"resolution", b.resolution}, {"tolerance", 1e-9},
                             {"unconverged", b.unconverged}, {"max_error", b.max_error},
                             {"seconds_1_thread_runs", b.seconds_1}, {"seconds_2_threads_runs", b.seconds_2},
                             {"seconds_1_thread", one}, {"seconds_2_threads", two}, {"speedup_2_threads", one / two}});
  }
  return doc;
}

nlohmann::ordered_json render_report(const BenchArgs& args) {
  const auto r = bench::run_render_benchmark(args.quick);
  return {{"benchmark", "render"},
          {"size", r.size},
          {"direct_crop", r.crop},
          {"seconds", {{"lambert_ambient", r.seconds_lambert}, {"tables", r.seconds_tables}, {"direct_crop", r.seconds_direct}}},
          {"ratios", {{"tables_vs_lambert", r.tables_vs_lambert}, {"direct_vs_tables", r.direct_vs_tables}}}};
}

/// The real-time tables' accuracy report: Markdown to --markdown, or to stdout.
int realtime_report(const BenchArgs& args) {
  std::vector<std::string> words{"ganzfeld", "bench", "realtime"};
  if (args.quick) words.push_back("--quick");
  if (args.repeats > 0) words.insert(words.end(), {"--repeats", std::to_string(args.repeats)});
  if (!args.markdown.empty()) words.insert(words.end(), {"--markdown", args.markdown});
  bench::RealtimeOptions options;
  options.quick = args.quick;
  options.repeats = bake_repeats(args);
  const std::string md = bench::realtime_markdown(options, shell_line(words));
  if (args.markdown.empty()) std::cout << md;
  else write_text_atomically(args.markdown, md);
  return 0;
}

}  // namespace

void add_bench_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("bench", "benchmarks that print ratios measured in one run");
  auto args = std::make_shared<BenchArgs>();
  cmd->add_option("what", args->what, "cubature | bake | render | realtime")->required();
  add_json_flag(*cmd, args->json);
  cmd->add_flag("--quick", args->quick, "a small sample (CI); the full run takes minutes");
  cmd->add_option("--cases", args->cases, "cases per integrand family (cubature; default 200, quick 4)");
  cmd->add_option("--repeats", args->repeats, "runs of each bake timing (default 5, quick 1); medians and spread");
  cmd->add_option("--markdown", args->markdown,
                  "cubature: also write the report (docs/performance.md) to FILE; realtime: write docs/realtime.md");
  cmd->add_option("--plot", args->plot, "cubature: also write the work-precision plot (PNG) to FILE");
  cmd->callback([&action, args] {
    action = [args] {
      if (args->what == "realtime") return realtime_report(*args);
      nlohmann::ordered_json doc;
      if (args->what == "cubature") doc = cubature_report(*args);
      else if (args->what == "bake") doc = bake_report(*args);
      else if (args->what == "render") doc = render_report(*args);
      else throw InputError("unknown benchmark '" + args->what + "'; allowed: cubature, bake, render, realtime");
      if (args->json) {
        std::cout << doc.dump(2) << "\n";
        return 0;
      }
      if (args->what == "cubature") {
        std::printf("evaluations of each competitor / ours to reach error %.0e (geometric mean; > = capped cases)\n",
                    doc["ratio_tolerance"].get<double>());
        std::printf("%-20s %5s %7s %8s %9s %9s %9s %9s %9s %9s %9s\n", "family", "cases", "missed", "oracle", "hcub_lune",
                    "hcub_naive", "pcub_lune", "boost_gk", "boost_ts", "mc_err", "dishonest");
        for (const auto& f : doc["families"]) {
          auto ratio = [&](const char* who) { return f["evals_ratio"].value(who, 0.0); };
          std::printf("%-20s %5d %7.4f %8.3g %9.3g %9.3g %9.3g %9.3g %9.3g %9.2g %9.4f\n", f["name"].get<std::string>().c_str(),
                      f["cases"].get<int>(), f["missed_rate"].get<double>(), ratio("oracle"), ratio("hcubature_lune"),
                      ratio("hcubature_naive"), ratio("pcubature_lune"), ratio("boost_gauss_kronrod"), ratio("boost_tanh_sinh"),
                      f["mc_error_ratio_equal_time"].get<double>(), f["dishonest_rate"].get<double>());
        }
      } else if (args->what == "render") {
        std::printf("%dx%d sphere: Lambert + ambient %.3f s, tables (3 lights, 2 lobes) %.3f s, direct %dx%d crop %.3f s\n"
                    "per pixel: tables / Lambert = %.2f, direct / tables = %.3g\n",
                    doc["size"].get<int>(), doc["size"].get<int>(), doc["seconds"]["lambert_ambient"].get<double>(),
                    doc["seconds"]["tables"].get<double>(), doc["direct_crop"].get<int>(), doc["direct_crop"].get<int>(),
                    doc["seconds"]["direct_crop"].get<double>(), doc["ratios"]["tables_vs_lambert"].get<double>(),
                    doc["ratios"]["direct_vs_tables"].get<double>());
      } else {
        for (const auto& t : doc["tables"])
          std::printf("%-22s g %s tol 1e-9: median %.2f s (1 thread), %.2f s (2 threads), speed-up %.2f, unconverged %lld\n",
                      t["model"].get<std::string>().c_str(), t["resolution"].dump().c_str(), t["seconds_1_thread"].get<double>(),
                      t["seconds_2_threads"].get<double>(), t["speedup_2_threads"].get<double>(), t["unconverged"].get<long long>());
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
