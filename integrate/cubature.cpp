#include "integrate/cubature.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

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

template <int D>
struct ByError {
  bool operator()(const Panel<D>& a, const Panel<D>& b) const {
    return a.error != b.error ? a.error < b.error : a.id > b.id;
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
    panel.error = std::abs(volume * (kk - gg)) + rounding;
    double worst = -1.0;
    for (int d = 0; d < D; ++d) {
      const double e = std::abs(kk - gauss_in_axis[d]);
      if (e > worst) {
        worst = e;
        panel.split_axis = d;
      }
    }
    if (!(std::isfinite(panel.value) && std::isfinite(panel.error))) {
      // A non-finite integrand value poisons nothing downstream: flag it as unresolvable.
      panel.value = 0.0;
      panel.error = std::numeric_limits<double>::infinity();
    }
  }

  long long evaluations() const { return evaluations_; }

 private:
  const PanelIntegrand<D>& integrand_;
  std::array<double, panel_nodes(D)> values_{};
  long long evaluations_ = 0;
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
  Engine<D> engine(integrand);
  std::vector<Panel<D>> heap;
  long long next_id = 0;

  // Step 1: the initial grid.
  std::array<std::size_t, D> counts;
  std::size_t total = 1;
  for (int d = 0; d < D; ++d) {
    counts[d] = cuts[d].size() - 1;
    total *= counts[d];
  }
  for (std::size_t flat = 0; flat < total; ++flat) {
    Panel<D> p;
    std::size_t rest = flat;
    for (int d = D - 1; d >= 0; --d) {
      const std::size_t index = rest % counts[d];
      rest /= counts[d];
      p.lo[d] = cuts[d][index];
      p.hi[d] = cuts[d][index + 1];
    }
    bool empty = false;
    for (int d = 0; d < D; ++d) empty = empty || !(p.hi[d] > p.lo[d]);
    if (empty) continue;
    p.id = next_id++;
    engine.evaluate(p);
    heap.push_back(p);
  }
  std::make_heap(heap.begin(), heap.end(), ByError<D>());

  auto summed_error = [&] {
    CompensatedSum s;
    for (const auto& p : heap) s.add(p.error);
    return s.value();
  };

  // Step 3: bisect the worst panel until the tolerance is met or the budget is spent.
  std::vector<Panel<D>> frozen;  // too small to split further (resolution limit of doubles)
  double frozen_error = 0.0;
  double error = summed_error();
  long long iterations = 0;
  const long long cost = 2LL * panel_nodes(D);
  while (!heap.empty() && error + frozen_error > options.abs_tol &&
         engine.evaluations() + cost <= options.max_evaluations) {
    std::pop_heap(heap.begin(), heap.end(), ByError<D>());
    Panel<D> worst = heap.back();
    heap.pop_back();
    const int axis = worst.split_axis;
    const double mid = 0.5 * (worst.lo[axis] + worst.hi[axis]);
    if (!(mid > worst.lo[axis] && mid < worst.hi[axis]) ||
        worst.hi[axis] - worst.lo[axis] < 1e-15 * std::max(1.0, std::abs(mid))) {
      frozen_error += worst.error;
      frozen.push_back(worst);
      error -= worst.error;
      continue;
    }
    Panel<D> left = worst, right = worst;
    left.hi[axis] = mid;
    right.lo[axis] = mid;
    left.id = next_id++;
    right.id = next_id++;
    engine.evaluate(left);
    engine.evaluate(right);
    heap.push_back(left);
    std::push_heap(heap.begin(), heap.end(), ByError<D>());
    heap.push_back(right);
    std::push_heap(heap.begin(), heap.end(), ByError<D>());
    error += left.error + right.error - worst.error;
    // The running sum drifts by rounding; recompute it exactly now and then and before stopping.
    if (++iterations % 256 == 0 || error + frozen_error <= options.abs_tol) error = summed_error();
  }

  CompensatedSum value, err;
  for (const auto* set : {&heap, &frozen})
    for (const auto& p : *set) {
      value.add(p.value);
      err.add(p.error);
    }
  Estimate out;
  out.value = value.value();
  out.error = err.value();
  out.evaluations = engine.evaluations();
  out.converged = std::isfinite(out.error) && out.error <= options.abs_tol;
  if (!std::isfinite(out.value)) {
    out.value = 0.0;
    out.converged = false;
  }
  return out;
}

template Estimate adaptive_cubature<1>(const PanelIntegrand<1>&, const std::array<std::vector<double>, 1>&,
                                       const CubatureOptions&);
template Estimate adaptive_cubature<2>(const PanelIntegrand<2>&, const std::array<std::vector<double>, 2>&,
                                       const CubatureOptions&);

}  // namespace ganzfeld
