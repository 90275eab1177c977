// Fits the free parameters of a model to data (fit/samples.h) under a metric (fit/metrics.h).
//
// The optimizer is NLopt's, derivative-free (ganzfeld's models give f only) and bound-constrained
// (the unit box of fit/parameters.h). The local search is PRAXIS (Brent 1973, "Algorithms for
// Minimization without Derivatives", ch. 7: conjugate directions with the principal axes of the
// objective's quadratic form), which follows long narrow valleys — hvd-fit's lump radius and
// exponent trade off along one, since n/R² alone sets a sharp lump's width; BOBYQA (Powell 2009,
// trust regions on interpolated quadratic models) is the alternative, measured against it in
// docs/fitting.md. Several starts: the first at the start spec's values, the others at the points
// of a Halton sequence in the unit box (feasible ones: a point the model's factory refuses, e.g.
// kd + ks > 1, is skipped). Each local search stops when its step falls below `xtol` in the unit
// box, or one step changes the objective by less than 1e-12 of itself, or the objective falls
// below kExactFit (the data reproduced to eight digits: no further start is run); the best point of
// all starts is the result. docs/fitting.md says why NLopt and not Ceres.
//
// Converged means: the local search that found the best point stopped on one of those criteria,
// not on its evaluation budget, the time limit, an interruption or NLopt's round-off limit. A fit
// that did not converge still returns its best point, and says so.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "fit/metrics.h"
#include "fit/samples.h"

namespace ganzfeld::fit {

/// An objective below this (E_rel or E_log below 1e-8: the data reproduced to eight digits) ends the
/// search: no other start could do materially better.
inline constexpr double kExactFit = 1e-16;

struct FitProgress {
  int start = 0, starts = 0;  ///< the local search running (1-based) and how many are planned
  long long evaluations = 0;  ///< so far, all starts
  long long budget = 0;       ///< starts × evaluations per start
  double best = 0.0;          ///< the best objective so far
};

enum class LocalSearch { praxis, bobyqa };
const char* to_string(LocalSearch local);
/// Throws InputError naming the text and the choices.
LocalSearch parse_local_search(const std::string& text);

struct FitOptions {
  Metric metric = Metric::ngan;
  LocalSearch local = LocalSearch::praxis;
  std::vector<std::string> fixed;  ///< "KEY=VALUE" (fit/parameters.h)
  int starts = 4;                  ///< local searches, the first from the start spec
  int max_evaluations = 4000;      ///< per local search
  double max_seconds = 0.0;        ///< all starts together; 0: no limit
  double xtol = 1e-7;              ///< step tolerance in the unit box
  /// Polled after every evaluation; true stops the search (the best point so far is the result).
  std::function<bool()> interrupted;
  /// Called every few evaluations and once at the end.
  std::function<void(const FitProgress&)> progress;
};

struct FitResult {
  std::string spec;                                        ///< the best point as a model spec
  std::vector<std::pair<std::string, double>> parameters;  ///< the free parameters there
  MetricValues metrics, start_metrics;                     ///< at the best point and at the first start
  bool converged = false, interrupted = false;
  std::string stop_reason;               ///< why the best point's local search stopped (NLopt's result)
  std::vector<double> start_objectives;  ///< each local search's best objective, in run order
  int starts_run = 0;
  long long evaluations = 0;
  double seconds = 0.0;
};

/// Fits `model_spec` (its values are the first start) to `data`. Throws InputError for a model
/// that cannot be fitted (fit/parameters.h) or options out of range.
FitResult fit_model(const FitData& data, const std::string& model_spec, const FitOptions& options);

}  // namespace ganzfeld::fit
