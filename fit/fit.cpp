#include "fit/fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include <nlopt.h>

#include "fit/parameters.h"
#include "models/spec.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::fit {

namespace {

/// The objective of a point the model's factory refuses, as a multiple of (1 + the first start's):
/// worse than any point the search has seen, without the infinities BOBYQA's models cannot take.
constexpr double kInfeasibleFactor = 4.0;
/// Halton points tried per start before the start is given up as infeasible.
constexpr int kStartTries = 64;
/// Progress is reported every this many evaluations.
constexpr int kProgressEvery = 16;
/// A local search ends when one step changes the objective by less than this fraction.
constexpr double kObjectiveTolerance = 1e-12;
/// The seed of NLopt's generator for the first start (PRAXIS's random steps).
constexpr unsigned long kSeed = 20060101;
/// The first step (PRAXIS) or trust-region radius (BOBYQA) in the unit box.
constexpr double kInitialStep = 0.05;

constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89};

/// The radical inverse of `index` in base `base` (Halton 1960).
double radical_inverse(unsigned index, unsigned base) {
  double result = 0.0, f = 1.0 / base;
  for (; index > 0; index /= base, f /= base) result += f * (index % base);
  return result;
}

struct Search {
  Search(const FitData& d, const ParameterSpace& s, const FitOptions& o) : data(d), space(s), options(o) {}
  const FitData& data;
  const ParameterSpace& space;
  const FitOptions& options;
  nlopt_opt opt = nullptr;
  util::Stopwatch watch;
  long long evaluations = 0, budget = 0;
  int start = 0;
  double infeasible = std::numeric_limits<double>::max();
  // The best point of all starts.
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
  MetricValues best_metrics;
  int best_start = -1;
  // The best point of the running start.
  double start_best = std::numeric_limits<double>::infinity();
  bool interrupted = false;

  std::vector<double> model_units(const double* u) const {
    std::vector<double> x;
    for (std::size_t k = 0; k < space.free().size(); ++k) x.push_back(space.free()[k].from_unit(u[k]));
    return x;
  }

  /// The objective at unit point u; nothing when the model's factory refuses the point.
  std::optional<std::pair<double, MetricValues>> evaluate(const double* u) const {
    ModelPtr model;
    try {
      model = parse_model(space.spec_at(model_units(u)));
    } catch (const InputError&) { return std::nullopt; }
    const MetricValues m = measure(data, model_values(data, *model));
    const double j = objective(options.metric, m);
    if (!std::isfinite(j)) return std::nullopt;
    return std::make_pair(j, m);
  }

  double operator()(const double* u) {
    ++evaluations;
    const auto value = evaluate(u);
    const double j = value ? value->first : infeasible;
    start_best = std::min(start_best, j);
    if (value && j < best) {
      best = j;
      best_x = model_units(u);
      best_metrics = value->second;
      best_start = start;
    }
    if (options.interrupted && options.interrupted()) {
      interrupted = true;
      nlopt_force_stop(opt);
    }
    if (options.max_seconds > 0.0 && watch.seconds() > options.max_seconds) nlopt_force_stop(opt);
    if (options.progress && evaluations % kProgressEvery == 0)
      options.progress({start, options.starts, evaluations, budget, best});
    return j;
  }
};

double nlopt_objective(unsigned, const double* u, double*, void* data) { return (*static_cast<Search*>(data))(u); }

bool converged_result(nlopt_result r) {
  return r == NLOPT_SUCCESS || r == NLOPT_STOPVAL_REACHED || r == NLOPT_FTOL_REACHED || r == NLOPT_XTOL_REACHED;
}

std::string reason(nlopt_result r, bool interrupted, bool timed_out) {
  if (interrupted) return "interrupted";
  if (timed_out && r == NLOPT_FORCED_STOP) return "time limit reached";
  switch (r) {
    case NLOPT_SUCCESS: return "success";
    case NLOPT_STOPVAL_REACHED: return "exact fit (objective below 1e-16)";
    case NLOPT_FTOL_REACHED: return "objective change below tolerance";
    case NLOPT_XTOL_REACHED: return "step below tolerance";
    case NLOPT_MAXEVAL_REACHED: return "evaluation budget reached";
    case NLOPT_MAXTIME_REACHED: return "time limit reached";
    case NLOPT_ROUNDOFF_LIMITED: return "round-off limited";
    case NLOPT_FORCED_STOP: return "stopped";
    default: return std::string("NLopt failure: ") + nlopt_result_to_string(r);
  }
}

}  // namespace

const char* to_string(LocalSearch local) { return local == LocalSearch::praxis ? "praxis" : "bobyqa"; }

LocalSearch parse_local_search(const std::string& text) {
  if (text == "praxis") return LocalSearch::praxis;
  if (text == "bobyqa") return LocalSearch::bobyqa;
  throw InputError({"unknown ", Named{"local"}, " '" + text + "'; allowed: praxis (default), bobyqa"});
}

FitResult fit_model(const FitData& data, const std::string& model_spec, const FitOptions& options) {
  if (options.starts < 1 || options.starts > 1000)
    throw InputError({Named{"starts", std::to_string(options.starts)}, " is not allowed; allowed: 1..1000"});
  if (options.max_evaluations < 1)
    throw InputError({Named{"max_evals", std::to_string(options.max_evaluations)}, " is not allowed; allowed: >= 1"});
  if (!(options.max_seconds >= 0.0) || !std::isfinite(options.max_seconds))
    throw InputError({Named{"max_seconds"}, " must be a finite number >= 0 (0: no limit)"});
  const ParameterSpace space(model_spec, options.fixed);
  const std::size_t n = space.free().size();
  if (n > std::size(kPrimes))
    throw InputError({"model '" + model_spec + "' has " + std::to_string(n) + " free parameters; at most " +
                          std::to_string(std::size(kPrimes)) + " can be fitted (fix some with ",
                      Named{"fixed"}, ")"});

  Search search(data, space, options);
  search.budget = static_cast<long long>(options.starts) * options.max_evaluations;
  std::unique_ptr<nlopt_opt_s, void (*)(nlopt_opt)> opt(
      nlopt_create(options.local == LocalSearch::praxis ? NLOPT_LN_PRAXIS : NLOPT_LN_BOBYQA, static_cast<unsigned>(n)),
      nlopt_destroy);
  if (!opt) throw std::runtime_error("NLopt could not create a BOBYQA optimizer");
  search.opt = opt.get();
  nlopt_set_lower_bounds1(opt.get(), 0.0);
  nlopt_set_upper_bounds1(opt.get(), 1.0);
  nlopt_set_min_objective(opt.get(), nlopt_objective, &search);
  nlopt_set_xtol_abs1(opt.get(), options.xtol);
  nlopt_set_ftol_rel(opt.get(), kObjectiveTolerance);
  nlopt_set_stopval(opt.get(), kExactFit);
  nlopt_set_maxeval(opt.get(), options.max_evaluations);
  nlopt_set_initial_step1(opt.get(), kInitialStep);

  FitResult result;
  std::vector<double> u0;
  for (const FreeParameter& f : space.free()) u0.push_back(f.to_unit(f.start));
  const auto first = search.evaluate(u0.data());
  if (!first) throw InputError("the start point '" + space.spec_at(space.start()) + "' is not a model");
  result.start_metrics = first->second;
  search.infeasible = kInfeasibleFactor * (1.0 + first->first);

  nlopt_result best_code = NLOPT_FAILURE;
  unsigned halton = 1;
  bool timed_out = false;
  for (int s = 0; s < options.starts && !search.interrupted && !timed_out && !(search.best <= kExactFit); ++s) {
    std::vector<double> u = u0;
    if (s > 0) {  // the next feasible Halton point
      bool found = false;
      for (int tries = 0; tries < kStartTries && !found; ++tries, ++halton) {
        for (std::size_t k = 0; k < n; ++k) u[k] = radical_inverse(halton, kPrimes[k]);
        found = search.evaluate(u.data()).has_value();
      }
      if (!found) break;
    }
    search.start = s + 1;
    search.start_best = std::numeric_limits<double>::infinity();
    if (options.max_seconds > 0.0) {
      const double left = options.max_seconds - search.watch.seconds();
      if (left <= 0.0) {
        timed_out = true;
        break;
      }
      nlopt_set_maxtime(opt.get(), left);
    }
    double value = 0.0;
    nlopt_srand(kSeed + static_cast<unsigned long>(s));  // PRAXIS draws random steps: the same run, the same fit
    const nlopt_result code = nlopt_optimize(opt.get(), u.data(), &value);
    timed_out = options.max_seconds > 0.0 && search.watch.seconds() > options.max_seconds;
    result.start_objectives.push_back(search.start_best);
    ++result.starts_run;
    if (search.best_start == s + 1) best_code = code;
  }
  if (search.best_x.empty()) {  // nothing beat the first point's value: it is the best
    search.best_x = space.start();
    search.best_metrics = first->second;
  }
  result.spec = parse_model(space.spec_at(search.best_x))->spec();
  for (std::size_t k = 0; k < n; ++k) result.parameters.emplace_back(space.free()[k].name, search.best_x[k]);
  result.metrics = search.best_metrics;
  result.interrupted = search.interrupted;
  result.converged = !search.interrupted && converged_result(best_code);
  result.stop_reason = reason(best_code, search.interrupted, timed_out);
  result.evaluations = search.evaluations;
  result.seconds = search.watch.seconds();
  if (options.progress)
    options.progress({search.start, options.starts, search.evaluations, search.budget, search.best});
  return result;
}

}  // namespace ganzfeld::fit
