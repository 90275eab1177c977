#include "integrate/cubature.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "models/registry.h"
#include "util/error.h"

namespace ganzfeld {

namespace {

/// Null rules per axis: degrees 13, 12, …, 8, taken in pairs (13, 12), (11, 10), (9, 8).
constexpr int kNullRules = 6;
/// A pair of null rules at most this fraction of the next lower pair, twice in a row, marks the
/// asymptotic regime (Berntsen, Espelid & Genz 1991; DCUHRE's and Cuhre's 1/5): the smooth part
/// of the integrand's Legendre expansion decays there, and |K − G| bounds K's error by orders.
constexpr double kAsymptoticRatio = 0.2;
/// Outside it the axis' error is at least this times the largest pair. Over 2·10^5 positions of
/// a kink |x − u| and of a jump [x > u] between the outermost nodes of one panel, K15's error
/// was at most 0.25 (kink) and 0.72 (jump) times the largest pair (tests/integrate_test.cpp,
/// NullRulesBoundKinksAndJumpsInOnePanel, checks the bound).
constexpr double kNonAsymptoticFactor = 2.0;
/// A half whose nodes, extrapolated to a side, miss the integrand on that side's line by more
/// than this times its highest pair of null rules (the polynomial interpolant's own error there,
/// measured below 0.5 of it on smooth panels) has something between its outermost nodes and the
/// side: a kink or a jump that no node sees.
constexpr double kInterpolationScale = 2.0;
/// The bound on what hides in a gap of width w next to a side where the extrapolation misses by
/// Δ: a jump hidden there errs by at most Δ·w, a kink by Δ·w/2 (its slope change times its
/// distance from the side is Δ); twice Δ·w.
constexpr double kHiddenFactor = 2.0;

/// The G7/K15 pair on [-1, 1], all 15 nodes ascending, Gauss weights 0 on Kronrod-only nodes;
/// the null rules; the interpolating polynomial's weights at either end of [-1, 1].
struct Rule {
  std::array<double, kRuleNodes> x{}, w_kronrod{}, w_gauss{};
  /// Null rule m (degree 13 - m: it integrates every polynomial up to that degree to 0) is
  /// w_kronrod · q_(14-m)(x), q_k the polynomials orthonormal on the nodes under the Kronrod
  /// weights; each scaled to the Euclidean norm of (K - G), so that null[0] is K - G itself.
  std::array<std::array<double, kRuleNodes>, kNullRules> null{};
  /// Lagrange weights of the 15 nodes at x = -1 ([0]) and x = +1 ([1]).
  std::array<std::array<double, kRuleNodes>, 2> at_end{};
};

Rule make_rule() {
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
  // Gram–Schmidt (twice, in long double) on x^k gives the orthonormal q_k on the nodes.
  using Long = long double;
  std::vector<std::array<Long, kRuleNodes>> q;
  for (int k = 0; k < kRuleNodes; ++k) {
    std::array<Long, kRuleNodes> p;
    for (int i = 0; i < kRuleNodes; ++i) p[i] = k == 0 ? 1.0L : q.back()[i] * out.x[i];
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& previous : q) {
        Long dot = 0;
        for (int i = 0; i < kRuleNodes; ++i) dot += out.w_kronrod[i] * p[i] * previous[i];
        for (int i = 0; i < kRuleNodes; ++i) p[i] -= dot * previous[i];
      }
    Long norm = 0;
    for (int i = 0; i < kRuleNodes; ++i) norm += out.w_kronrod[i] * p[i] * p[i];
    for (int i = 0; i < kRuleNodes; ++i) p[i] /= std::sqrt(norm);
    q.push_back(p);
  }
  Long difference_norm = 0;
  for (int i = 0; i < kRuleNodes; ++i)
    difference_norm += (out.w_kronrod[i] - out.w_gauss[i]) * (out.w_kronrod[i] - out.w_gauss[i]);
  for (int m = 0; m < kNullRules; ++m) {
    std::array<Long, kRuleNodes> w;
    Long norm = 0, along_difference = 0;
    for (int i = 0; i < kRuleNodes; ++i) {
      w[i] = out.w_kronrod[i] * q[kRuleNodes - 1 - m][i];
      norm += w[i] * w[i];
      along_difference += w[i] * (out.w_kronrod[i] - out.w_gauss[i]);
    }
    const Long scale = std::sqrt(difference_norm / norm) * (along_difference < 0 ? -1 : 1);
    for (int i = 0; i < kRuleNodes; ++i) out.null[m][i] = static_cast<double>(w[i] * scale);
  }
  for (int end = 0; end < 2; ++end)
    for (int i = 0; i < kRuleNodes; ++i) {
      Long weight = 1;
      for (int k = 0; k < kRuleNodes; ++k)
        if (k != i) weight *= ((end == 0 ? -1.0L : 1.0L) - out.x[k]) / (Long(out.x[i]) - out.x[k]);
      out.at_end[end][i] = static_cast<double>(weight);
    }
  return out;
}

const Rule& rule() {
  static const Rule r = make_rule();
  return r;
}

/// The width of the gap between a panel's outermost node and its side, per unit half-width.
double side_gap() { return 1.0 - rule().x[kRuleNodes - 1]; }

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

constexpr int panel_nodes(int D) { return D == 1 ? kRuleNodes : kRuleNodes * kRuleNodes; }
/// Nodes on one side of a panel: the other axis' nodes (one point in 1-D).
constexpr int side_nodes(int D) { return D == 1 ? 1 : kRuleNodes; }
/// The integrand on a line across one axis, at the nodes of the other axis.
template <int D>
using Line = std::array<double, side_nodes(D)>;
constexpr int kNoLine = -1;

template <int D>
struct Panel {
  std::array<double, D> lo{}, hi{};
  double value = 0.0;
  double rule_error = 0.0;             // the rules' estimate (section 2 of cubature.h), rounding included
  std::array<double, D> axis_error{};  // its parts per axis (what bisecting that axis reduces)
  std::array<double, 2 * D> hidden{};  // bound on what hides next to each side: [2d] lower, [2d + 1] upper
  std::array<int, 2 * D> side_line{};  // the integrand on that side's line (Refinement::lines_), or kNoLine
  double error = 0.0;                  // rule_error + hidden
  int split_axis = 0;
  long long id = 0;  // creation order: a deterministic tie-break
  std::array<bool, D> asymptotic{};
  std::array<double, D> interpolation_scale{};  // kInterpolationScale × the highest null pair, per axis
  std::array<Line<D>, D> centre_line{};         // the integrand on the line bisecting each axis

  /// The error and the axis to bisect: the one whose rule error and side bounds are largest
  /// (bisecting across a side halves its gap).
  void total() {
    error = rule_error;
    double worst = -1.0;
    for (int d = 0; d < D; ++d) {
      const double sides = hidden[2 * d] + hidden[2 * d + 1];
      error += sides;
      if (axis_error[d] + sides > worst) {
        worst = axis_error[d] + sides;
        split_axis = d;
      }
    }
  }
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

/// A panel's nodes extrapolated to its sides: [d][0] the lower side across axis d, [d][1] the upper.
template <int D>
using SideValues = std::array<std::array<Line<D>, 2>, D>;

template <int D>
class Engine {
 public:
  Engine(const PanelIntegrand<D>& integrand) : integrand_(integrand) {}

  /// The Kronrod nodes of `panel` along each axis. A line on a side (evaluate_line) uses the
  /// same nodes along the other axis, bit for bit, so that it meets the panel's extrapolation.
  static std::array<std::array<double, kRuleNodes>, D> nodes_of(const Panel<D>& panel) {
    const Rule& r = rule();
    std::array<std::array<double, kRuleNodes>, D> nodes;
    for (int d = 0; d < D; ++d) {
      const double centre = 0.5 * (panel.lo[d] + panel.hi[d]), half = 0.5 * (panel.hi[d] - panel.lo[d]);
      for (int m = 0; m < kRuleNodes; ++m) nodes[d][m] = centre + half * r.x[m];
    }
    return nodes;
  }

  SideValues<D> evaluate(Panel<D>& panel) {
    const Rule& r = rule();
    const std::array<std::array<double, kRuleNodes>, D> nodes = nodes_of(panel);
    std::array<double, D> half;
    for (int d = 0; d < D; ++d) half[d] = 0.5 * (panel.hi[d] - panel.lo[d]);
    std::array<std::span<const double>, D> spans;
    for (int d = 0; d < D; ++d) spans[d] = nodes[d];
    integrand_(spans, values_);
    evaluations_ += panel_nodes(D);

    // Kronrod in every axis; Gauss in every axis; Gauss in one axis only; per axis d, the
    // Kronrod rule in the other axes at each node of d (what the null rules of d apply to).
    constexpr int centre = kRuleNodes / 2;
    double kk = 0.0, gg = 0.0, magnitude = 0.0;
    std::array<double, D> gauss_in_axis{};
    std::array<std::array<double, kRuleNodes>, D> along{};
    SideValues<D> sides{};
    if constexpr (D == 1) {
      for (int a = 0; a < kRuleNodes; ++a) {
        kk += r.w_kronrod[a] * values_[a];
        gg += r.w_gauss[a] * values_[a];
        magnitude += r.w_kronrod[a] * std::abs(values_[a]);
        along[0][a] = values_[a];
        for (int end = 0; end < 2; ++end) sides[0][end][0] += r.at_end[end][a] * values_[a];
      }
      gauss_in_axis[0] = gg;
      panel.centre_line[0][0] = values_[centre];
    } else {
      for (int a = 0; a < kRuleNodes; ++a)
        for (int b = 0; b < kRuleNodes; ++b) {
          const double v = values_[a * kRuleNodes + b];
          kk += r.w_kronrod[a] * r.w_kronrod[b] * v;
          gg += r.w_gauss[a] * r.w_gauss[b] * v;
          gauss_in_axis[0] += r.w_gauss[a] * r.w_kronrod[b] * v;
          gauss_in_axis[1] += r.w_kronrod[a] * r.w_gauss[b] * v;
          magnitude += r.w_kronrod[a] * r.w_kronrod[b] * std::abs(v);
          along[0][a] += r.w_kronrod[b] * v;
          along[1][b] += r.w_kronrod[a] * v;
          for (int end = 0; end < 2; ++end) {
            sides[0][end][b] += r.at_end[end][a] * v;
            sides[1][end][a] += r.at_end[end][b] * v;
          }
        }
      for (int m = 0; m < kRuleNodes; ++m) {
        panel.centre_line[0][m] = values_[centre * kRuleNodes + m];
        panel.centre_line[1][m] = values_[m * kRuleNodes + centre];
      }
    }
    double volume = 1.0;
    for (int d = 0; d < D; ++d) volume *= half[d];
    volume = std::abs(volume);
    panel.value = volume * kk;
    // Rounding floor: the rule cannot resolve below a few ulps of the panel's L1 mass; null rules
    // at that level are noise, and noise has no asymptotic regime to tell.
    const double noise = 50.0 * std::numeric_limits<double>::epsilon() * magnitude;
    // K⊗K − G⊗G = (K⊗K − G⊗K) + (G⊗K − G⊗G), the second ≈ K⊗K − K⊗G: the axes' errors add, and
    // their signs may cancel in the raw difference. The sum of their magnitudes cannot cancel and
    // is taken when larger (tests/independent_reference_test.cpp: the raw difference alone
    // undershoots cook-torrance g at θ_i 35°, θ_j 70°).
    double raw_axes = 0.0, axes = 0.0;
    for (int d = 0; d < D; ++d) {
      const double gauss_difference = std::abs(kk - gauss_in_axis[d]);
      std::array<double, kNullRules> n{};
      for (int m = 0; m < kNullRules; ++m) {
        double s = 0.0;
        for (int a = 0; a < kRuleNodes; ++a) s += r.null[m][a] * along[d][a];
        n[m] = std::abs(s);
      }
      // Pairs of consecutive degrees: an even or odd integrand about the centre leaves one of
      // each pair at 0, the pair's magnitude does not depend on that phase.
      const double e1 = std::hypot(n[0], n[1]), e2 = std::hypot(n[2], n[3]);
      const double e3 = std::hypot(n[4], n[5]);
      panel.asymptotic[d] =
          e1 <= std::max(kAsymptoticRatio * e2, noise) && e2 <= std::max(kAsymptoticRatio * e3, noise);
      panel.interpolation_scale[d] = std::max(kInterpolationScale * e1, noise);
      const double axis = panel.asymptotic[d]
                              ? gauss_difference
                              : std::max(gauss_difference, kNonAsymptoticFactor * std::max({e1, e2, e3}));
      raw_axes += gauss_difference;
      axes += axis;
      panel.axis_error[d] = volume * axis;
    }
    panel.rule_error = volume * (std::max({std::abs(kk - gg), raw_axes, axes}) + noise);
    panel.total();
    if (!(std::isfinite(panel.value) && std::isfinite(panel.error))) {
      // Bisecting moves every node, so a point or line where the integrand is non-finite that a
      // node happened to hit usually lies off the nodes of the halves (a midpoint is on an edge).
      panel.value = 0.0;
      panel.rule_error = panel.error = std::numeric_limits<double>::infinity();
      panel.split_axis = widest_axis(panel);
    }
    return sides;
  }

  /// The integrand on the line through side `end` of `panel` across `axis`, at the panel's nodes
  /// along the other axis (one point in 1-D): what check_side compares the extrapolation with.
  /// False when a value there is not finite (an integrable singularity on the box's end, say):
  /// such a line cannot tell a hidden kink from the singularity, and the side stays unchecked.
  bool evaluate_line(const Panel<D>& panel, int axis, int end, Line<D>& line) {
    const std::array<std::array<double, kRuleNodes>, D> nodes = nodes_of(panel);
    std::array<std::span<const double>, D> spans;
    const double side = end == 0 ? panel.lo[axis] : panel.hi[axis];
    for (int d = 0; d < D; ++d)
      spans[d] = d == axis ? std::span<const double>(&side, 1) : std::span<const double>(nodes[d]);
    integrand_(spans, line);
    evaluations_ += side_nodes(D);
    for (double v : line)
      if (!std::isfinite(v)) return false;
    return true;
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

  /// Step 1: one panel per cell of the caller's grid, each bisected once unless the caller
  /// trusts its grid (CubatureOptions::bisect_initial_panels).
  void seed(const std::array<std::vector<double>, D>& cuts) {
    std::size_t total = 1;
    for (int d = 0; d < D; ++d) total *= cuts[d].size() - 1;
    std::vector<Panel<D>> cells;
    for (std::size_t flat = 0; flat < total && !cancelled(); ++flat) {
      Panel<D> p;
      if (!grid_cell(cuts, flat, p)) continue;
      p.side_line.fill(kNoLine);
      p.id = next_id_++;
      const SideValues<D> extrapolated = engine_.evaluate(p);
      if (options_.bisect_initial_panels && !unresolved(p)) {
        for (int axis = 0; axis < D; ++axis)
          for (int end = 0; end < 2; ++end) check_new_line(p, extrapolated, axis, end);
        p.total();
      }
      cells.push_back(p);
    }
    for (const Panel<D>& p : cells)
      if (options_.bisect_initial_panels && splittable(p)) bisect(p);
      else open(p);
    std::make_heap(heap_.begin(), heap_.end(), ByError<D>());
    error_ = open_error();
    seeded_ = true;
  }

  /// Step 3: bisect the worst panel until the tolerance is met, the budget is spent or an
  /// unresolved panel is too small to bisect (then no budget can make the result converge).
  void refine() {
    const long long cost = kBisectionEvaluations<D>;
    while (!heap_.empty() && !gave_up_ && (unresolved_ > 0 || error_ + frozen_error_ > options_.abs_tol) &&
           engine_.evaluations() + cost <= options_.max_evaluations && !cancelled()) {
      const Panel<D> worst = pop_worst();
      if (splittable(worst)) bisect(worst);
      else freeze(worst);
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
    return mid > p.lo[axis] && mid < p.hi[axis] && !(p.hi[axis] - p.lo[axis] < 1e-15 * std::max(1.0, std::abs(mid)));
  }

  Panel<D> pop_worst() {
    std::pop_heap(heap_.begin(), heap_.end(), ByError<D>());
    const Panel<D> worst = heap_.back();
    heap_.pop_back();
    return worst;
  }

  /// A new open panel: pushed onto the heap, or only appended while seeding (heapified after).
  void open(const Panel<D>& p) {
    heap_.push_back(p);
    if (seeded_) std::push_heap(heap_.begin(), heap_.end(), ByError<D>());
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

  /// The sides of a half of `parent` bisected across `axis` (`upper`: the half above the cut).
  /// Across the axis the outer side is the parent's (same line, same nodes along it; its bound
  /// halves with the gap), the cut is a new side whose line is the parent's centre line. Along
  /// the axis the sides are half as long: their bound is shared, and their line, which no longer
  /// matches the half's nodes, only marks a side still to check (bisect evaluates a new one).
  static void inherit_sides(Panel<D>& half, const Panel<D>& parent, int axis, bool upper, int cut) {
    for (int d = 0; d < D; ++d)
      for (int end = 0; end < 2; ++end) {
        const int k = 2 * d + end;
        const bool is_cut = d == axis && end == (upper ? 0 : 1);
        half.hidden[k] = is_cut ? 0.0 : 0.5 * parent.hidden[k];
        half.side_line[k] = is_cut ? cut : parent.side_line[k];
      }
  }

  /// Compares a half's nodes, extrapolated to its side `end` across `axis`, with the integrand on
  /// that side's line (section 2 of cubature.h). Past the interpolant's own error, something
  /// hides in the gap: the bound stays on the side, whose line is kept to recheck the next half
  /// there. Within it, the bound is the half's own (added to its rule error) and the side is
  /// settled. A half not yet in the asymptotic regime extrapolates poorly: its bound is its own
  /// and the side is rechecked when it is bisected.
  void check_side(Panel<D>& half, const SideValues<D>& extrapolated, int axis, int end) const {
    const int k = 2 * axis + end;
    if (half.side_line[k] == kNoLine) return;
    const Line<D>& line = lines_[half.side_line[k]];
    double miss = 0.0, length = 1.0;
    if constexpr (D == 1) {
      miss = std::abs(extrapolated[0][end][0] - line[0]);
    } else {
      length = 0.5 * (half.hi[1 - axis] - half.lo[1 - axis]);
      for (int m = 0; m < kRuleNodes; ++m) miss += rule().w_kronrod[m] * std::abs(extrapolated[axis][end][m] - line[m]);
    }
    const double bound = kHiddenFactor * miss * side_gap() * 0.5 * (half.hi[axis] - half.lo[axis]) * length;
    if (half.asymptotic[axis] && miss > half.interpolation_scale[axis]) {
      half.hidden[k] = bound;
      return;
    }
    half.hidden[k] = 0.0;
    half.rule_error += bound;
    if (half.asymptotic[axis]) half.side_line[k] = kNoLine;
  }

  /// check_side against a new line through the side (Engine::evaluate_line): for a side of the
  /// initial grid, and for a side not yet settled once its line no longer meets the half's nodes
  /// (the half is shorter along it than the panel that made the line).
  void check_new_line(Panel<D>& panel, const SideValues<D>& extrapolated, int axis, int end) {
    const int k = 2 * axis + end;
    Line<D> line;
    if (!engine_.evaluate_line(panel, axis, end, line)) {
      panel.side_line[k] = kNoLine;
      return;
    }
    lines_.push_back(line);
    panel.side_line[k] = static_cast<int>(lines_.size() - 1);
    check_side(panel, extrapolated, axis, end);
  }

  void bisect(const Panel<D>& parent) {
    const int axis = parent.split_axis;
    const double mid = 0.5 * (parent.lo[axis] + parent.hi[axis]);
    Panel<D> lower = parent, upper = parent;
    lower.hi[axis] = mid;
    upper.lo[axis] = mid;
    lower.id = next_id_++;
    upper.id = next_id_++;
    const SideValues<D> lower_sides = engine_.evaluate(lower);
    const SideValues<D> upper_sides = engine_.evaluate(upper);
    if (unresolved(parent) || unresolved(lower) || unresolved(upper)) {
      lower.side_line.fill(kNoLine);
      upper.side_line.fill(kNoLine);
      lower.hidden.fill(0.0);
      upper.hidden.fill(0.0);
    } else {
      lines_.push_back(parent.centre_line[axis]);
      const int cut = static_cast<int>(lines_.size() - 1);
      inherit_sides(lower, parent, axis, false, cut);
      inherit_sides(upper, parent, axis, true, cut);
      // A half next to a side of the parent across the axis that is still open (a gap there
      // may hide a strip the parent's nodes never saw) rechecks its sides along the axis even
      // where the parent had settled them: the parent's nodes along them missed that strip too.
      const bool lower_next_to_open = parent.side_line[2 * axis] != kNoLine;
      const bool upper_next_to_open = parent.side_line[2 * axis + 1] != kNoLine;
      for (int d = 0; d < D; ++d)
        for (int end = 0; end < 2; ++end) {
          if (d == axis) {
            check_side(lower, lower_sides, axis, end);
            check_side(upper, upper_sides, axis, end);
            continue;
          }
          const bool open = parent.side_line[2 * d + end] != kNoLine;
          if (open || lower_next_to_open) check_new_line(lower, lower_sides, d, end);
          if (open || upper_next_to_open) check_new_line(upper, upper_sides, d, end);
        }
      lower.total();
      upper.total();
    }
    if (seeded_ && unresolved(parent)) --unresolved_;
    open(lower);
    open(upper);
    if (!seeded_) return;
    error_ += finite_error(lower) + finite_error(upper) - finite_error(parent);
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
  std::vector<Panel<D>> heap_;    // open panels, a max-heap by ByError once seeded
  std::vector<Panel<D>> frozen_;  // too small to bisect further
  std::vector<Line<D>> lines_;    // the integrand on every cut line made so far (Panel::side_line)
  double error_ = 0.0;            // summed error of heap_, kept up to date incrementally
  double frozen_error_ = 0.0;     // summed error of frozen_
  int unresolved_ = 0;            // unresolved panels in heap_
  bool gave_up_ = false;          // an unresolved panel was frozen
  bool seeded_ = false;           // step 1 is done: heap_ is a heap
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
Estimate adaptive_cubature(const PanelIntegrand<D>& integrand, const std::array<std::vector<double>, D>& cuts,
                           const CubatureOptions& options) {
  if (!(options.abs_tol >= kEngineMinTolerance) || !std::isfinite(options.abs_tol))
    throw InputError("adaptive_cubature: tolerance " + format_number(options.abs_tol) +
                     " is not allowed; expected a finite absolute tolerance >= " + format_number(kEngineMinTolerance));
  if (options.max_evaluations < panel_nodes(D))
    throw InputError("adaptive_cubature: a budget of " + std::to_string(options.max_evaluations) +
                     " evaluations is below one panel; allowed: >= " + std::to_string(panel_nodes(D)));
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
