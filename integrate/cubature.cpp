#include "integrate/cubature.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "models/registry.h"
#include "util/error.h"

namespace ganzfeld {

namespace {

/// The G7/K15 pair on [-1, 1], all 15 nodes ascending, Gauss weights 0 on Kronrod-only nodes.
struct Rule {
  std::array<double, kRuleNodes> x{}, w_kronrod{}, w_gauss{};
};

const Rule& rule() {
  static const Rule r = [] {
    Rule out;
    const auto& xk = boost::math::quadrature::gauss_kronrod<double, kRuleNodes>::abscissa();
    const auto& wk = boost::math::quadrature::gauss_kronrod<double, kRuleNodes>::weights();
    const auto& xg = boost::math::quadrature::gauss<double, 7>::abscissa();
    const auto& wg = boost::math::quadrature::gauss<double, 7>::weights();
    constexpr int half = kRuleNodes / 2;  // node 0 is the centre
    for (int m = 0; m <= half; ++m) {
      double gauss_weight = 0.0;
      for (std::size_t q = 0; q < xg.size(); ++q)
        if (std::abs(xg[q] - xk[m]) < 1e-12) gauss_weight = wg[q];
      for (int sign : {-1, 1}) {
        const int index = half + sign * m;
        out.x[index] = sign * xk[m];
        out.w_kronrod[index] = wk[m];
        out.w_gauss[index] = gauss_weight;
      }
    }
    return out;
  }();
  return r;
}

/// Neumaier's compensated sum.
struct CompensatedSum {
  double sum = 0.0, compensation = 0.0;
  void add(double v) {
    const double t = sum + v;
    compensation += std::abs(sum) >= std::abs(v) ? (sum - t) + v : (v - t) + sum;
    sum = t;
  }
  double value() const { return sum + compensation; }
};

template <int D>
struct Panel {
  std::array<double, D> lo, hi;
  double value = 0.0, error = 0.0;
  int split_axis = 0;
  long long id = 0;  // creation order: a deterministic tie-break
};

/// A panel on which the rule met a NaN or an infinity (or overflowed) has no estimate at all; it
/// carries value 0 and an infinite error, so that it is bisected first and blocks convergence.
template <int D>
bool unresolved(const Panel<D>& p) {
  return std::isinf(p.error);
}

template <int D>
struct ByError {
  bool operator()(const Panel<D>& a, const Panel<D>& b) const {
    if (a.error != b.error) return a.error < b.error;
    // Unresolved panels newest first: depth-first, a region where the integrand is non-finite is
    // bisected down to the resolution limit (and gives up) in ~50 steps per axis; breadth-first
    // it would double its panels at every level and only stop when the budget is spent.
    if (unresolved(a)) return a.id < b.id;
    return a.id > b.id;
  }
};

constexpr int panel_nodes(int D) { return D == 1 ? kRuleNodes : kRuleNodes * kRuleNodes; }

template <int D>
class Engine {
 public:
  Engine(const PanelIntegrand<D>& integrand) : integrand_(integrand) {}

  void evaluate(Panel<D>& panel) {
    const Rule& r = rule();
    std::array<std::array<double, kRuleNodes>, D> nodes;
    std::array<double, D> half;
    for (int d = 0; d < D; ++d) {
      const double centre = 0.5 * (panel.lo[d] + panel.hi[d]);
      half[d] = 0.5 * (panel.hi[d] - panel.lo[d]);
      for (int m = 0; m < kRuleNodes; ++m) nodes[d][m] = centre + half[d] * r.x[m];
    }
    std::array<std::span<const double>, D> spans;
    for (int d = 0; d < D; ++d) spans[d] = nodes[d];
    integrand_(spans, values_);
    evaluations_ += panel_nodes(D);

    // Kronrod in every axis; Gauss in every axis; Gauss in one axis only (per-axis indicator).
    double kk = 0.0, gg = 0.0, magnitude = 0.0;
    std::array<double, D> gauss_in_axis{};
    if constexpr (D == 1) {
      for (int a = 0; a < kRuleNodes; ++a) {
        kk += r.w_kronrod[a] * values_[a];
        gg += r.w_gauss[a] * values_[a];
        magnitude += r.w_kronrod[a] * std::abs(values_[a]);
      }
      gauss_in_axis[0] = gg;
    } else {
      for (int a = 0; a < kRuleNodes; ++a)
        for (int b = 0; b < kRuleNodes; ++b) {
          const double v = values_[a * kRuleNodes + b];
          kk += r.w_kronrod[a] * r.w_kronrod[b] * v;
          gg += r.w_gauss[a] * r.w_gauss[b] * v;
          gauss_in_axis[0] += r.w_gauss[a] * r.w_kronrod[b] * v;
          gauss_in_axis[1] += r.w_kronrod[a] * r.w_gauss[b] * v;
          magnitude += r.w_kronrod[a] * r.w_kronrod[b] * std::abs(v);
        }
    }
    double volume = 1.0;
    for (int d = 0; d < D; ++d) volume *= half[d];
    panel.value = volume * kk;
    // Rounding floor: the rule cannot resolve below a few ulps of the panel's L1 mass.
    const double rounding = 50.0 * std::numeric_limits<double>::epsilon() * volume * magnitude;
    // K⊗K − G⊗G = (K⊗K − G⊗K) + (G⊗K − G⊗G), the second ≈ K⊗K − K⊗G: the axes' errors add, and
    // their signs may cancel in the raw difference. The sum of their magnitudes cannot cancel and
    // is taken when larger (tests/independent_reference_test.cpp: the raw difference alone
    // undershoots cook-torrance g at θ_i 35°, θ_j 70°).
    double worst = -1.0, axes = 0.0;
    for (int d = 0; d < D; ++d) {
      const double e = std::abs(kk - gauss_in_axis[d]);
      axes += e;
      if (e > worst) {
        worst = e;
        panel.split_axis = d;
      }
    }
    panel.error = std::abs(volume) * std::max(std::abs(kk - gg), axes) + rounding;
    if (!(std::isfinite(panel.value) && std::isfinite(panel.error))) {
      // Bisecting moves every node, so a point or line where the integrand is non-finite that a
      // node happened to hit usually lies off the nodes of the halves (a midpoint is on an edge).
      panel.value = 0.0;
      panel.error = std::numeric_limits<double>::infinity();
      panel.split_axis = widest_axis(panel);
    }
  }

  long long evaluations() const { return evaluations_; }

 private:
  /// The per-axis differences are meaningless when non-finite. Bisecting the widest axis
  /// (relative to its position, as splittable() measures it) means that an unresolved panel is
  /// frozen, and the refinement given up, only once it is tiny in every axis.
  static int widest_axis(const Panel<D>& p) {
    int widest = 0;
    double best = -1.0;
    for (int d = 0; d < D; ++d) {
      const double width = (p.hi[d] - p.lo[d]) / std::max(1.0, std::abs(0.5 * (p.lo[d] + p.hi[d])));
      if (width > best) {
        best = width;
        widest = d;
      }
    }
    return widest;
  }

  const PanelIntegrand<D>& integrand_;
  std::array<double, panel_nodes(D)> values_{};
  long long evaluations_ = 0;
};

/// Steps 1 and 3 of the algorithm (cubature.h): the panels still open to bisection, kept as a
/// max-heap on their error, and those too small to bisect. Unresolved panels (infinite error)
/// are counted apart from the summed error, which stays finite so that it can still be updated.
template <int D>
class Refinement {
 public:
  Refinement(const PanelIntegrand<D>& integrand, const CubatureOptions& options)
      : engine_(integrand), options_(options) {}

  /// Step 1: one panel per cell of the caller's grid.
  void seed(const std::array<std::vector<double>, D>& cuts) {
    std::size_t total = 1;
    for (int d = 0; d < D; ++d) total *= cuts[d].size() - 1;
    for (std::size_t flat = 0; flat < total && !cancelled(); ++flat) {
      Panel<D> p;
      if (!grid_cell(cuts, flat, p)) continue;
      p.id = next_id_++;
      engine_.evaluate(p);
      heap_.push_back(p);
      if (unresolved(p)) ++unresolved_;
    }
    std::make_heap(heap_.begin(), heap_.end(), ByError<D>());
    error_ = open_error();
  }

  /// Step 3: bisect the worst panel until the tolerance is met, the budget is spent or an
  /// unresolved panel is too small to bisect (then no budget can make the result converge).
  void refine() {
    const long long cost = 2LL * panel_nodes(D);
    while (!heap_.empty() && !gave_up_ && (unresolved_ > 0 || error_ + frozen_error_ > options_.abs_tol) &&
           engine_.evaluations() + cost <= options_.max_evaluations && !cancelled()) {
      const Panel<D> worst = pop_worst();
      if (splittable(worst))
        bisect(worst);
      else
        freeze(worst);
    }
  }

  /// The value omits the unresolved panels; their infinite error (added apart: an infinity would
  /// turn the compensated sum into NaN) makes the result not converged.
  Estimate result() const {
    CompensatedSum value, err;
    bool any_unresolved = false;
    for (const auto* set : {&heap_, &frozen_})
      for (const auto& p : *set) {
        if (unresolved(p)) {
          any_unresolved = true;
          continue;
        }
        value.add(p.value);
        err.add(p.error);
      }
    Estimate out;
    out.value = value.value();
    out.error = any_unresolved ? std::numeric_limits<double>::infinity() : err.value();
    out.evaluations = engine_.evaluations();
    out.converged = std::isfinite(out.error) && out.error <= options_.abs_tol && !cancelled();
    if (!std::isfinite(out.value)) {
      out.value = 0.0;
      out.converged = false;
    }
    return out;
  }

 private:
  /// Cell `flat` of the grid, the last axis running fastest; false for an empty cell (a
  /// repeated cut), which has nothing to integrate and would only waste a rule.
  static bool grid_cell(const std::array<std::vector<double>, D>& cuts, std::size_t flat, Panel<D>& p) {
    for (int d = D - 1; d >= 0; --d) {
      const std::size_t count = cuts[d].size() - 1;
      const std::size_t index = flat % count;
      flat /= count;
      p.lo[d] = cuts[d][index];
      p.hi[d] = cuts[d][index + 1];
    }
    for (int d = 0; d < D; ++d)
      if (!(p.hi[d] > p.lo[d])) return false;
    return true;
  }

  /// The caller's flag (CubatureOptions::cancel): a seed cut short omits cells, so a cancelled
  /// result is never converged.
  bool cancelled() const { return options_.cancel && options_.cancel->load(std::memory_order_relaxed); }

  /// Below ~1e-15 of its position a bisection no longer shrinks the panel (resolution of doubles).
  static bool splittable(const Panel<D>& p) {
    const int axis = p.split_axis;
    const double mid = 0.5 * (p.lo[axis] + p.hi[axis]);
    return mid > p.lo[axis] && mid < p.hi[axis] &&
           !(p.hi[axis] - p.lo[axis] < 1e-15 * std::max(1.0, std::abs(mid)));
  }

  Panel<D> pop_worst() {
    std::pop_heap(heap_.begin(), heap_.end(), ByError<D>());
    const Panel<D> worst = heap_.back();
    heap_.pop_back();
    return worst;
  }

  void push(const Panel<D>& p) {
    heap_.push_back(p);
    std::push_heap(heap_.begin(), heap_.end(), ByError<D>());
    if (unresolved(p)) ++unresolved_;
  }

  /// The panel's error stays in the total but no longer drives the refinement.
  void freeze(const Panel<D>& p) {
    frozen_.push_back(p);
    if (unresolved(p)) {
      --unresolved_;
      gave_up_ = true;
      return;
    }
    frozen_error_ += p.error;
    error_ -= p.error;
  }

  void bisect(const Panel<D>& worst) {
    const int axis = worst.split_axis;
    const double mid = 0.5 * (worst.lo[axis] + worst.hi[axis]);
    Panel<D> left = worst, right = worst;
    left.hi[axis] = mid;
    right.lo[axis] = mid;
    left.id = next_id_++;
    right.id = next_id_++;
    engine_.evaluate(left);
    engine_.evaluate(right);
    if (unresolved(worst)) --unresolved_;
    push(left);
    push(right);
    error_ += finite_error(left) + finite_error(right) - finite_error(worst);
    // The running sum drifts by rounding; recompute it exactly now and then and before stopping.
    if (++iterations_ % 256 == 0 || (unresolved_ == 0 && error_ + frozen_error_ <= options_.abs_tol))
      error_ = open_error();
  }

  /// Unresolved panels are counted in unresolved_ instead: inf - inf would make the sum NaN.
  static double finite_error(const Panel<D>& p) { return unresolved(p) ? 0.0 : p.error; }

  /// The open panels' summed finite error, exactly (error_ is an incremental update of it).
  double open_error() const {
    CompensatedSum s;
    for (const auto& p : heap_)
      if (!unresolved(p)) s.add(p.error);
    return s.value();
  }

  Engine<D> engine_;
  const CubatureOptions& options_;
  std::vector<Panel<D>> heap_;    // open panels, a max-heap by ByError
  std::vector<Panel<D>> frozen_;  // too small to bisect further
  double error_ = 0.0;            // summed error of heap_, kept up to date incrementally
  double frozen_error_ = 0.0;     // summed error of frozen_
  int unresolved_ = 0;            // unresolved panels in heap_
  bool gave_up_ = false;          // an unresolved panel was frozen
  long long next_id_ = 0, iterations_ = 0;
};

}  // namespace

std::vector<double> tidy_cuts(std::vector<double> lines, double lo, double hi, double min_gap) {
  std::vector<double> inner;
  for (double x : lines)
    if (std::isfinite(x) && x > lo + min_gap && x < hi - min_gap) inner.push_back(x);
  std::sort(inner.begin(), inner.end());
  std::vector<double> out{lo};
  for (double x : inner)
    if (x - out.back() >= min_gap) out.push_back(x);
  out.push_back(hi);
  return out;
}

template <int D>
Estimate adaptive_cubature(const PanelIntegrand<D>& integrand,
                           const std::array<std::vector<double>, D>& cuts,
                           const CubatureOptions& options) {
  Refinement<D> refinement(integrand, options);
  refinement.seed(cuts);
  refinement.refine();
  return refinement.result();
}

template Estimate adaptive_cubature<1>(const PanelIntegrand<1>&, const std::array<std::vector<double>, 1>&,
                                       const CubatureOptions&);
template Estimate adaptive_cubature<2>(const PanelIntegrand<2>&, const std::array<std::vector<double>, 2>&,
                                       const CubatureOptions&);

void check_tolerance(const std::string& name, double tol) {
  if (!std::isfinite(tol) || tol < kMinTolerance || tol > kMaxTolerance)
    throw InputError({Named{name, format_number(tol)}, " is not allowed; expected an absolute tolerance in [" +
                                                           format_number(kMinTolerance) + ", " +
                                                           format_number(kMaxTolerance) + "]"});
}

void check_max_evaluations(const std::string& name, long long max_evaluations) {
  if (max_evaluations < kMinEvaluations)
    throw InputError({Named{name, std::to_string(max_evaluations)},
                      " is too small; allowed: >= " + std::to_string(kMinEvaluations)});
}

}  // namespace ganzfeld
