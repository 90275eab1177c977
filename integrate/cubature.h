// Globally adaptive tensor-product Gauss–Kronrod cubature on a box in 1 or 2 dimensions.
//
// The algorithm in three steps (after QUADPACK's qag and Genz & Malik's adaptive scheme, as in
// S. G. Johnson's hcubature.c):
//  1. Start from a grid of panels whose lines are given by the caller (the known lobe peaks,
//     widths and boundary layers of the integrand: MassHints, models/mass_hints.h), so that the first nodes
//     cannot all miss a sharp lobe.
//  2. On each panel apply the 15-point Kronrod rule in every axis (15^D nodes) and its embedded
//     7-point Gauss rule; the panel's error is the larger of |K⊗K − G⊗G| and the sum of the
//     per-axis differences |K⊗K − G⊗K| + |K⊗K − K⊗G| (whose signs can cancel in the former),
//     deliberately raw and pessimistic (no QUADPACK power-law rescaling) so that the estimate
//     bounds the true error. The per-axis differences also say which axis to split.
//  3. Repeatedly bisect the panel with the largest error along its worst axis until the summed
//     error is below the absolute tolerance or the evaluation budget is spent. Not converging is
//     a result (converged = false), never an exception and never a silent wrong value.
//     A panel whose nodes meet a NaN or an infinity has no estimate: it is bisected first, which
//     usually moves an isolated non-finite point or line off the nodes. While such a panel
//     remains (budget spent, or bisected to the resolution of doubles: a non-finite region) the
//     result is not converged, with an infinite error and a value that omits those panels.
// Deterministic: panels are processed sequentially in a fixed order and summed with Neumaier's
// compensated sum, so the same input gives the same bits whatever runs around it.
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace ganzfeld {

/// A value with its error estimate: every number ganzfeld computes carries one.
struct Estimate {
  double value = 0.0;
  double error = 0.0;
  long long evaluations = 0;
  bool converged = true;
};

struct CubatureOptions {
  double abs_tol = 1e-9;                     ///< stop when the summed error estimate <= this
  /// Budget per integral; beyond it: not converged. The initial grid is always evaluated (a
  /// result needs at least one rule per panel), so it may exceed a budget smaller than itself.
  long long max_evaluations = 50'000'000;
  /// When set, read before every panel: once it holds true the integral stops where it is and
  /// is returned not converged (a caller that no longer wants the answer: a deadline, a client
  /// gone, a shutdown). The caller owns the flag and knows why it set it.
  const std::atomic<bool>* cancel = nullptr;
};

/// Number of nodes per axis of the Kronrod rule.
inline constexpr int kRuleNodes = 15;

/// The integrand sees a whole panel at once: nodes[d] holds the kRuleNodes abscissas of axis d
/// and it fills values[a * kRuleNodes + b] = F(nodes[0][a], nodes[1][b]) (D = 2) or
/// values[a] = F(nodes[0][a]) (D = 1). Panel-wise calls let it hoist trigonometry and batch f.
template <int D>
using PanelIntegrand =
    std::function<void(const std::array<std::span<const double>, D>& nodes, std::span<double> values)>;

/// Integrates over the box whose axis d is cut by the sorted lines cuts[d] (first = lower
/// bound, last = upper bound, at least two per axis).
template <int D>
Estimate adaptive_cubature(const PanelIntegrand<D>& integrand,
                           const std::array<std::vector<double>, D>& cuts,
                           const CubatureOptions& options);

/// Sorts, removes duplicates and drops lines closer than `min_gap` to a neighbour, keeping both
/// ends: a helper for building `cuts` from hints.
std::vector<double> tidy_cuts(std::vector<double> lines, double lo, double hi, double min_gap);

/// The absolute tolerances a caller may ask for (the command line's --tol, the Python module's tol=).
inline constexpr double kMinTolerance = 1e-15;
inline constexpr double kMaxTolerance = 1.0;
/// The smallest evaluation budget per integral a caller may give (--max-evals, max_evals=).
inline constexpr long long kMinEvaluations = 1000;
/// Refuse (InputError naming the parameter `name`, "tol" or "max_evals", which each front end
/// spells: --tol, tol=) a tolerance that is not finite or outside [kMinTolerance, kMaxTolerance],
/// and a budget below kMinEvaluations.
void check_tolerance(const std::string& name, double tol);
void check_max_evaluations(const std::string& name, long long max_evaluations);

}  // namespace ganzfeld
