// Globally adaptive tensor-product Gauss–Kronrod cubature on a box in 1 or 2 dimensions.
//
// The algorithm in three steps (after QUADPACK's qag and Genz & Malik's adaptive scheme, as in
// S. G. Johnson's hcubature.c):
//  1. Start from a grid of panels whose lines are given by the caller (the known lobe peaks,
//     widths and boundary layers of the integrand: MassHints, models/mass_hints.h), so that the
//     first nodes cannot all miss a sharp lobe. Unless the caller says its lines come from such
//     hints (CubatureOptions::bisect_initial_panels), every initial panel is bisected once at the
//     start, so that none is accepted before its halves have been compared with it.
//  2. On each panel apply the 15-point Kronrod rule in every axis (15^D nodes) and its embedded
//     7-point Gauss rule. Per axis, the larger of |K⊗K − G⊗K| (the Gauss rule in that axis only)
//     and, where the panel is not in the rules' asymptotic regime, twice the largest of three
//     pairs of null rules of degrees 13 … 8 on the same nodes (Berntsen, Espelid & Genz, ACM
//     TOMS 17(4) 1991, as DCUHRE and Cuba's Cuhre use them): a kink or a jump inside a panel
//     makes the null rules decay slowly, where G7/K15's difference can vanish by chance. The
//     panel's error is the larger of |K⊗K − G⊗G| and the sum over the axes, raw and pessimistic
//     on purpose (no QUADPACK power-law rescaling), plus a check of each side: where a panel's
//     nodes, extrapolated to a side, disagree with the integrand on that side's line, a kink or
//     jump may hide in the gap between the outermost nodes and the side (0.43% of the panel's
//     width per end): a bound on it is added, and rechecked when that panel is bisected, until
//     a panel in the rules' asymptotic regime agrees with the line. The line of a cut made by
//     a bisection is the parent's centre line (no evaluation); the lines on the sides of the
//     initial grid, and new lines on a half's sides along the bisected axis (where the
//     parent's side was still open, or the half lies next to a side across the axis that is: a
//     strip hidden there was never seen along the other sides either) cost kRuleNodes
//     evaluations each (one in 1-D). A caller that trusts its grid (bisect_initial_panels off:
//     cuts placed at the integrand's creases and jumps, where a line has no one value to
//     compare) gets no lines on the initial grid's sides.
//  3. Repeatedly bisect the panel with the largest error along its worst axis until the summed
//     error is below the absolute tolerance or the evaluation budget is spent. Not converging is
//     a result (converged = false), never an exception and never a silent wrong value.
//     A panel whose nodes meet a NaN or an infinity has no estimate: it is bisected first, which
//     usually moves an isolated non-finite point or line off the nodes. While such a panel
//     remains (budget spent, or bisected to the resolution of doubles: a non-finite region) the
//     result is not converged, with an infinite error and a value that omits those panels.
// What no rule sees, no estimate bounds: a lobe narrower than the gaps between the nodes of the
// halves of an initial panel (measured on Genz's test families: ganzfeld bench genz,
// docs/reliability-genz.md).
// Deterministic: panels are processed sequentially in a fixed order and summed with Neumaier's
// compensated sum, so the same input gives the same bits whatever runs around it.
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <limits>
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
  double abs_tol = 1e-9;  ///< stop when the summed error estimate <= this
  /// Budget per integral; beyond it: not converged. The initial grid and its sides' lines are
  /// always evaluated (a result needs at least one rule per panel), so they may exceed a budget
  /// smaller than themselves;
  /// a budget smaller than one panel (kRuleNodes^D) is refused.
  long long max_evaluations = 50'000'000;
  /// Bisect every panel of the initial grid once before any is accepted: a lobe narrower than
  /// the gaps between a panel's nodes (up to 10% of its width) can hide from all of them, and
  /// only new nodes find it. Callers whose cuts come from the integrand's own mass hints
  /// (integrate/laws_integrals.cpp) turn it off: their panels are placed where the mass is.
  bool bisect_initial_panels = true;
  /// When set, read before every panel: once it holds true the integral stops where it is and
  /// is returned not converged (a caller that no longer wants the answer: a deadline, a client
  /// gone, a shutdown). The caller owns the flag and knows why it set it.
  const std::atomic<bool>* cancel = nullptr;
};

/// Number of nodes per axis of the Kronrod rule.
inline constexpr int kRuleNodes = 15;
/// The most evaluations one bisection costs: its two halves and, in 2-D, up to two new lines of
/// kRuleNodes on each (sides not yet settled, section 2 above). The refinement stops before a
/// bisection would pass the budget.
template <int D>
inline constexpr long long kBisectionEvaluations =
    D == 1 ? 2 * kRuleNodes : 2 * kRuleNodes* kRuleNodes + 4 * kRuleNodes;

/// The smallest absolute tolerance adaptive_cubature accepts: below the smallest normal double
/// the summed error estimates themselves lose their precision. (A front end's user is held to
/// kMinTolerance below, which check_tolerance enforces.)
inline constexpr double kEngineMinTolerance = std::numeric_limits<double>::min();

/// The integrand sees a whole panel at once: nodes[d] holds the abscissas of axis d and it fills
/// values[a * nodes[1].size() + b] = F(nodes[0][a], nodes[1][b]) (D = 2) or
/// values[a] = F(nodes[0][a]) (D = 1). Panel-wise calls let it hoist trigonometry and batch f.
/// An axis holds kRuleNodes abscissas, or one: the line through a panel's side, where the engine
/// checks what hides between the side and the outermost nodes (section 2 above).
template <int D>
using PanelIntegrand =
    std::function<void(const std::array<std::span<const double>, D>& nodes, std::span<double> values)>;

/// The PanelIntegrand of a function of one point, f(x) (D = 1) or f(x, y) (D = 2), called at
/// every node.
template <int D, class F>
PanelIntegrand<D> pointwise(F f) {
  return [f](const std::array<std::span<const double>, D>& nodes, std::span<double> values) {
    if constexpr (D == 1) {
      for (std::size_t a = 0; a < nodes[0].size(); ++a) values[a] = f(nodes[0][a]);
    } else {
      for (std::size_t a = 0; a < nodes[0].size(); ++a)
        for (std::size_t b = 0; b < nodes[1].size(); ++b) values[a * nodes[1].size() + b] = f(nodes[0][a], nodes[1][b]);
    }
  };
}

/// Integrates over the box whose axis d is cut by the sorted lines cuts[d] (first = lower
/// bound, last = upper bound, at least two per axis). Throws InputError (util/error.h) for a
/// tolerance that is not a finite number >= kEngineMinTolerance or a budget below one panel.
template <int D>
Estimate adaptive_cubature(const PanelIntegrand<D>& integrand, const std::array<std::vector<double>, D>& cuts,
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
