// ganzfeld fit: any model's free parameters fitted to measured or synthetic data (fit/fit.h), the
// metrics of the fit and the laws of data and fit; --report writes docs/fitting.md (fit/report.h).
// Ctrl-C stops the search and prints the best fit found so far (converged: false).
#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "fit/fit.h"
#include "fit/law_difference.h"
#include "fit/parameters.h"
#include "fit/report.h"
#include "models/registry.h"
#include "models/spec.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"

namespace ganzfeld::cli {

namespace {

struct FitArgs {
  std::string data, model, start, metric = "ngan", grid = "90x30x30", local = "praxis";
  std::vector<std::string> fixed;
  double max_theta = fit::SampleOptions{}.max_theta_deg;
  int starts = fit::FitOptions{}.starts, max_evaluations = fit::FitOptions{}.max_evaluations;
  double max_seconds = 0.0, tol = 1e-5;
  bool no_laws = false, json = false, quiet = false;
  // --report
  bool report = false, quick = false;
  std::string markdown, commit = "unknown", figures;
};

/// Set by SIGINT while a fit runs; the optimizer polls it after every evaluation.
std::atomic<bool> interrupt_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void on_interrupt(int) {
  interrupt_requested.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process
}

/// Installs the handler for the lifetime of the object, restores the previous one after.
class InterruptGuard {
 public:
  InterruptGuard() {
    interrupt_requested.store(false);
    previous_ = std::signal(SIGINT, on_interrupt);
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_); }

 private:
  void (*previous_)(int);
};

std::string degrees(double d) { return format_number(d); }

nlohmann::ordered_json estimate_json(const Estimate& e) {
  return {{"value", e.value}, {"error", e.error}, {"converged", e.converged}};
}

int run_fit(const FitArgs& args) {
  const InterruptGuard guard;  // from here: Ctrl-C while the data load also ends in the best fit (the start)
  if (args.data.empty() || args.model.empty()) throw InputError("fit needs --data SPEC and --model SPEC (or --report)");
  const fit::Metric metric = fit::parse_metric(args.metric);
  const fit::LocalSearch local = fit::parse_local_search(args.local);
  if (!args.no_laws) validate_tolerance(args.tol);
  fit::SampleOptions sampling;
  sampling.grid = fit::parse_grid(args.grid);
  sampling.max_theta_deg = args.max_theta;
  std::string model_spec = args.model;
  if (!args.start.empty()) {  // the start must be the same model, with other values
    const Spec model = fit::canonical_spec(args.model), start = fit::canonical_spec(args.start);
    bool same = model.terms.size() == start.terms.size();
    for (std::size_t k = 0; same && k < model.terms.size(); ++k)
      same = model.terms[k].model.name == start.terms[k].model.name;
    if (!same) throw InputError("--start '" + args.start + "' is not the model of --model '" + args.model + "'");
    model_spec = args.start;
  }
  const ModelPtr data = parse_model(args.data);
  fit::FitOptions options;
  options.metric = metric;
  options.local = local;
  options.fixed = args.fixed;
  options.starts = args.starts;
  options.max_evaluations = args.max_evaluations;
  options.max_seconds = args.max_seconds;
  fit::ParameterSpace(model_spec, options.fixed);  // refuse a model that cannot be fitted before sampling
  const fit::FitData samples = fit::sample_data(*data, sampling);

  // The bar runs over the evaluation budget and is completed when the search ends (most end early).
  const std::string model_name = fit::canonical_spec(model_spec).terms.front().model.name;
  auto bar = util::progress_bar("fit " + model_name, args.quiet || args.json);
  const auto budget = static_cast<std::uint64_t>(options.starts) * static_cast<std::uint64_t>(options.max_evaluations);
  if (bar)
    options.progress = [bar, budget](const fit::FitProgress& p) {
      bar(std::min(static_cast<std::uint64_t>(p.evaluations), budget - 1), budget);
    };
  options.interrupted = [] { return interrupt_requested.load(); };
  const fit::FitResult result = fit::fit_model(samples, model_spec, options);
  if (bar) bar(budget, budget);
  std::optional<fit::LawDifference> laws;
  if (!args.no_laws) laws = fit::law_difference(*data, *parse_model(result.spec), args.tol);

  if (args.json) {
    nlohmann::ordered_json doc;
    doc["data"] = data->spec();
    doc["model"] = args.model;
    doc["metric"] = fit::to_string(metric);
    doc["local"] = fit::to_string(options.local);
    doc["spec"] = result.spec;
    doc["parameters"] = nlohmann::ordered_json::object();
    for (const auto& [name, value] : result.parameters) doc["parameters"][name] = value;
    doc["fixed"] = args.fixed;
    auto metrics_json = [](const fit::MetricValues& m) {
      return nlohmann::ordered_json{
          {"ngan_relative", m.ngan_relative}, {"ngan_rms", m.ngan_rms}, {"log_rms", m.log_rms}};
    };
    doc["metrics"] = metrics_json(result.metrics);
    doc["start_metrics"] = metrics_json(result.start_metrics);
    doc["converged"] = result.converged;
    doc["interrupted"] = result.interrupted;
    doc["stop_reason"] = result.stop_reason;
    doc["starts"] = result.starts_run;
    doc["start_objectives"] = result.start_objectives;
    doc["evaluations"] = result.evaluations;
    doc["seconds"] = result.seconds;
    doc["samples"] = samples.size();
    doc["sampling"] = samples.source;
    doc["max_theta"] = args.max_theta;
    if (laws) {
      nlohmann::ordered_json points = nlohmann::ordered_json::array();
      for (const auto& p : laws->points)
        points.push_back({{"law", to_string(p.law)},
                          {"theta_i", p.theta_i_deg},
                          {"theta_j", p.theta_j_deg},
                          {"phi", p.phi_deg},
                          {"data", estimate_json(p.data)},
                          {"fit", estimate_json(p.fit)}});
      doc["laws"] = {{"tolerance", args.tol},
                     {"points", points},
                     {"max_difference", {{"g", laws->max_g}, {"h", laws->max_h}, {"a", laws->max_a}}}};
    }
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("fit %s to %s, %zu samples (%s, theta <= %s deg), metric %s\n", args.model.c_str(), data->spec().c_str(),
              samples.size(), samples.source.c_str(), degrees(args.max_theta).c_str(), fit::to_string(metric));
  std::printf("  %s\n", result.spec.c_str());
  std::printf("  ngan: E_rel %.4g (start %.4g), E %.4g 1/sr; log: E %.4g (start %.4g)\n", result.metrics.ngan_relative,
              result.start_metrics.ngan_relative, result.metrics.ngan_rms, result.metrics.log_rms,
              result.start_metrics.log_rms);
  std::printf("  %s (%s): %d start%s, %lld evaluations, %.2f s\n",
              result.converged ? "converged" : "NOT converged, best point so far", result.stop_reason.c_str(),
              result.starts_run, result.starts_run == 1 ? "" : "s", result.evaluations, result.seconds);
  if (laws) {
    for (Law law : {Law::h, Law::a, Law::g}) {
      std::printf("  %s:", to_string(law));
      for (const auto& p : laws->points) {
        if (p.law != law) continue;
        const std::string where =
            law == Law::h   ? degrees(p.theta_j_deg)
            : law == Law::a ? degrees(p.theta_i_deg)
                            : degrees(p.theta_i_deg) + "," + degrees(p.theta_j_deg) + "," + degrees(p.phi_deg);
        std::printf(" (%s) %.4f/%.4f", where.c_str(), p.data.value, p.fit.value);
      }
      std::printf("  data/fit\n");
    }
    if (!laws->converged) std::printf("  (some law integrals did not converge to --tol %g)\n", args.tol);
  }
  return 0;
}

}  // namespace

void add_fit_command(CLI::App& app, Action& action) {
  auto* cmd =
      app.add_subcommand("fit", "fit a model's parameters to measured or synthetic BRDF data (docs/fitting.md)");
  auto args = std::make_shared<FitArgs>();
  cmd->add_option("--data", args->data, "the data: merl:file=F, tabulated:file=F or any model spec");
  cmd->add_option("--model", args->model, "the model to fit (a spec: its values are the first start), e.g. hvd-fit");
  cmd->add_option("--start", args->start, "a spec of the same model whose values are the first start");
  cmd->add_option("--fixed", args->fixed, "KEY=VALUE[,KEY=VALUE...]: parameters held at a value")->delimiter(',');
  cmd->add_option("--metric", args->metric, "ngan (cosine-weighted relative L2, default) or log (cosine-weighted log)");
  cmd->add_option("--local", args->local, "the local search: praxis (default) or bobyqa (docs/fitting.md)");
  cmd->add_option("--grid", args->grid, "theta_h x theta_d x phi_d sample nodes (default 90x30x30; MERL: divisors)");
  cmd->add_option("--max-theta", args->max_theta,
                  "leave out pairs with theta_i or theta_o beyond (degrees, default 80)");
  cmd->add_option("--starts", args->starts, "local searches, the first from the start (default 4)");
  cmd->add_option("--max-evals", args->max_evaluations, "evaluations per local search (default 4000)");
  cmd->add_option("--max-seconds", args->max_seconds, "stop after this long with the best point (default 0: no limit)");
  cmd->add_option("--tol", args->tol, "absolute tolerance of the laws of data and fit (default 1e-5)");
  cmd->add_flag("--no-laws", args->no_laws, "skip the laws g, h, a of data and fit");
  cmd->add_flag("--json", args->json, "print one JSON document");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--report", args->report, "run the fitting report (recovery, cross-model table, disk view)");
  cmd->add_flag("--quick", args->quick, "--report: a small slice (seconds), as the tests run it");
  cmd->add_option("--markdown", args->markdown, "--report: write it as Markdown (docs/fitting.md)");
  cmd->add_option("--commit", args->commit, "--report: the commit stamped into it (scripts/gen-fitting-docs)");
  cmd->add_option("--figures", args->figures, "--report: where its disk figure goes (default: beside --markdown)");
  cmd->callback([&action, args] {
    action = [args] {
      if (!args->report) return run_fit(*args);
      if (args->markdown.empty()) throw InputError("--report needs --markdown FILE");
      check_writable(args->markdown);
      fit::ReportOptions options;
      options.quick = args->quick;
      options.commit = args->commit;
      options.markdown = args->markdown;
      options.figures = args->figures;
      std::vector<std::string> words{"ganzfeld", "fit", "--report"};
      if (args->quick) words.push_back("--quick");
      words.insert(words.end(), {"--markdown", args->markdown});
      if (!args->figures.empty()) words.insert(words.end(), {"--figures", args->figures});
      options.command = shell_line(words);
      options.log = args->quiet ? std::function<void(const std::string&)>{}
                                : [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
      const fit::Report report = fit::run_report(options);
      write_text_atomically(args->markdown, fit::report_markdown(report, options), "report");
      std::printf("fitting report: %d of %d targets met -> %s\n", report.targets_met(), report.targets_total(),
                  args->markdown.c_str());
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
