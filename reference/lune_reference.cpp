#include "reference/lune_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

namespace ganzfeld::reference {

namespace {
using std::numbers::pi;
const Vec3 kNormal{0, 0, 1};
const Vec3 kHemisphereEdge{1, 0, 0};  // any horizontal axis; the break points find the lobes
}  // namespace

LuneCoordinates::LuneCoordinates(const Vec3& pole, const Vec3& hemisphere_edge) {
  const Vec3 axis = glm::cross(n, pole);
  empty = glm::length(axis) <= 1e-12 && pole.z < 0.0;
  e = glm::length(axis) > 1e-12 ? glm::normalize(axis) : hemisphere_edge;
  b = glm::cross(e, n);
  const double psi_pole = std::atan2(glm::dot(pole, b), glm::dot(pole, n));
  psi_lo = std::max(-pi / 2, psi_pole - pi / 2);
  psi_hi = std::min(pi / 2, psi_pole + pi / 2);
}

Vec3 LuneCoordinates::direction(double t, double psi) const {
  return std::cos(t) * (std::cos(psi) * n + std::sin(psi) * b) + std::sin(t) * e;
}

std::pair<double, double> LuneCoordinates::coordinates(const Vec3& k) const {
  return {std::asin(std::clamp(glm::dot(k, e), -1.0, 1.0)), std::atan2(glm::dot(k, b), glm::dot(k, n))};
}

AntipodeCoordinates::AntipodeCoordinates(const Vec3& pole_, const Vec3& fixed) : pole(pole_), p(-fixed) {
  empty = glm::length(glm::cross(n, pole)) <= 1e-12 && pole.z < 0.0;
  // u: towards the zenith from p (so the horizon's rays are beta = ±pi/2), any horizontal axis at
  // p = ±n. As w × p, w = (p_y, -p_x, 0) horizontal across p: n - (n·p) p without the cancellation
  // of 1 - p_z^2 near the poles.
  const Vec3 across{p.y, -p.x, 0.0};
  u = glm::length(across) > 0.0 ? glm::normalize(glm::cross(across, p)) : kHemisphereEdge;
  v = glm::cross(p, u);
}

Vec3 AntipodeCoordinates::direction(double r, double beta) const {
  return std::cos(r) * p + std::sin(r) * (std::cos(beta) * u + std::sin(beta) * v);
}

namespace {
/// {r ∈ [0, pi] : a cos r + b sin r > 0} = {cos(r - atan2(b, a)) > 0}: one interval, or none.
std::pair<double, double> positive_arc(double a, double b) {
  if (a == 0.0 && b == 0.0) return {0.0, 0.0};
  const double phi = std::atan2(b, a);
  for (double shift : {0.0, 2 * pi, -2 * pi}) {
    const double lo = std::max(0.0, phi - pi / 2 + shift), hi = std::min(pi, phi + pi / 2 + shift);
    if (lo < hi) return {lo, hi};
  }
  return {0.0, 0.0};
}
}  // namespace

std::pair<double, double> AntipodeCoordinates::radii(double beta) const {
  const Vec3 d = std::cos(beta) * u + std::sin(beta) * v;
  const auto [lo, hi] = positive_arc(glm::dot(p, n), glm::dot(d, n));
  const auto [pole_lo, pole_hi] = positive_arc(glm::dot(p, pole), glm::dot(d, pole));
  return {std::max(lo, pole_lo), std::min(hi, pole_hi)};
}

double AntipodeCoordinates::beta(const Vec3& k) const { return std::atan2(glm::dot(k, v), glm::dot(k, u)); }

std::vector<double> cuts(double lo, double hi, const std::vector<double>& centres) {
  std::vector<double> out{lo, hi};
  for (double c : centres)
    for (double w : {-0.2, -0.05, 0.0, 0.05, 0.2})
      if (c + w > lo && c + w < hi) out.push_back(c + w);
  std::sort(out.begin(), out.end());
  // Merge cuts closer than 1e-9 (a peak on the edge axis lands at t = 1e-17, not 0).
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return b - a < 1e-9; }), out.end());
  return out;
}

namespace {

/// The L1 norm of f over the panels of `cut` by one unrefined gauss_kronrod<Points> per panel
/// (each panel's |integral| appended to *panel_integral when given): the size tolerances refer to.
template <unsigned Points, class F>
double rough_l1(F&& f, const std::vector<double>& cut, std::vector<double>* panel_integral = nullptr) {
  using Rule = boost::math::quadrature::gauss_kronrod<double, Points>;
  double l1 = 0.0;
  for (std::size_t k = 0; k + 1 < cut.size(); ++k) {
    double panel_l1 = 0.0;
    const double value = Rule::integrate(f, cut[k], cut[k + 1], 0, 1.0, nullptr, &panel_l1);
    if (panel_integral) panel_integral->push_back(std::abs(value));
    l1 += panel_l1;
  }
  return l1;
}

/// Each panel's relative tolerance (panels() below): options.tolerance, or with
/// options.global_tolerance that tolerance relative to the whole range's L1 norm (a rough
/// gauss_kronrod<Points> pass), and never tighter than `absolute` shared among the panels.
template <unsigned Points, class F>
std::vector<double> panel_tolerances(F&& f, const std::vector<double>& cut, const Options& options, double absolute) {
  const std::size_t count = cut.size() - 1;
  std::vector<double> tolerance(count, options.tolerance);
  if (!options.global_tolerance) return tolerance;
  std::vector<double> rough;
  const double l1 = rough_l1<Points>(f, cut, &rough);
  for (std::size_t k = 0; k < count; ++k)
    if (rough[k] > 0.0)
      tolerance[k] = std::max({options.tolerance, options.tolerance * l1 / rough[k], absolute / count / rough[k]});
  return tolerance;
}

/// ∫ over the panels of `cut` by gauss_kronrod<Points>; adds Boost's error estimates to *error.
/// Boost stops bisecting a panel when its error is below tolerance × |that panel's integral|; with
/// options.global_tolerance the tolerance is made relative to the whole range's L1 norm instead
/// (from one unrefined pass over the panels), so that a sliver panel next to a peak on the edge,
/// whose integral is below the rounding of its own error estimate, is not bisected to full depth.
/// `absolute` (0: none) is an error the whole range may have whatever its own size: an inner
/// integral near the lune's pole, 1e-90 in size and all cancellation noise (specular at j·n = 1e-6,
/// where (1 + k·mirror(j))/2 ~ 1e-12 is raised to the 8th power), then stops at the share of the
/// outer integral's tolerance that it can affect instead of bisecting noise to full depth.
template <unsigned Points, class F>
double panels(F&& f, const std::vector<double>& cut, const Options& options, double absolute, double* error) {
  using Rule = boost::math::quadrature::gauss_kronrod<double, Points>;
  const std::size_t count = cut.size() - 1;
  const std::vector<double> tolerance = panel_tolerances<Points>(f, cut, options, absolute);
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    double panel_error = 0.0;
    sum += Rule::integrate(f, cut[k], cut[k + 1], options.max_depth, tolerance[k], &panel_error);
    // Boost 1.74's recursive gauss_kronrod reports each leaf's |K - G| on [-1, 1], unscaled by the
    // leaf's half-width s_i (gauss_kronrod.hpp, recursive_adaptive_integrate): a panel 3e-6 wide
    // claimed 1e6 times its error, one 3 wide half of it. The leaves' true estimates e_i s_i sum
    // to at most the panel's half-width times the sum Boost returns.
    *error += panel_error * 0.5 * (cut[k + 1] - cut[k]);
  }
  return sum;
}

/// As panels(), by Boost's tanh_sinh on each panel (relative tolerance per panel as there; its
/// error is the difference of its last two levels, scaled to the panel).
template <class F>
double tanh_sinh_panels(F&& f, const std::vector<double>& cut, const Options& options, double absolute, double* error) {
  thread_local boost::math::quadrature::tanh_sinh<double> rule;  // integrate() is not const
  const std::size_t count = cut.size() - 1;
  const std::vector<double> tolerance = panel_tolerances<15>(f, cut, options, absolute);
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    double panel_error = 0.0;
    sum += rule.integrate(f, cut[k], cut[k + 1], tolerance[k], &panel_error);
    // Boost 1.74's tanh_sinh scales the integral and its L1 norm by the panel's half-width but
    // returns the error on [-1, 1] (tanh_sinh.hpp, integrate(f, a, b, ...)), as its
    // gauss_kronrod does (panels() above).
    *error += panel_error * 0.5 * (cut[k + 1] - cut[k]);
  }
  return sum;
}

/// The absolute error each inner integral of a nested one may have: tolerance × (the whole
/// integral's L1 norm) / (the outer span), which summed by the outer rule is the tolerance relative
/// to the whole (without Options::global_tolerance: none), or the inner integrals' half of
/// Options::absolute_tolerance spread over the span where that is larger. The L1 norm comes from a
/// cheap gauss_kronrod<15> pass, unrefined at both levels (it only scales the inner stopping rule;
/// the errors reported are Boost's own estimates either way).
template <class F>
double inner_tolerance(F& point, const std::vector<double>& outer_cut, const std::vector<double>& inner_cut,
                       const Options& options) {
  const double span = outer_cut.back() - outer_cut.front();
  const double absolute = 0.5 * options.absolute_tolerance / span;
  if (!options.global_tolerance) return absolute;
  const double l1 =
      rough_l1<15>([&](double x) { return rough_l1<15>([&](double y) { return point(x, y); }, inner_cut); }, outer_cut);
  return std::max(options.tolerance * l1 / span, absolute);
}

/// Nested: outer over `outer_cut`, inner over `inner_cut`; point(outer, inner) is the integrand,
/// each inner integral to inner_tolerance.
template <unsigned Points, class F>
Value nested(F&& point, const std::vector<double>& outer_cut, const std::vector<double>& inner_cut,
             const Options& options) {
  Value out;
  const double span = outer_cut.back() - outer_cut.front();
  const double inner_absolute = inner_tolerance(point, outer_cut, inner_cut, options);
  double worst_inner = 0.0;
  auto inner = [&](double x) {
    double error = 0.0;
    const double value =
        panels<Points>([&](double y) { return point(x, y); }, inner_cut, options, inner_absolute, &error);
    worst_inner = std::max(worst_inner, error);
    return value;
  };
  out.value = panels<Points>(inner, outer_cut, options, 0.5 * options.absolute_tolerance, &out.error);
  out.inner_error = worst_inner * span;
  return out;
}

/// nested() with tanh_sinh_panels() at both levels. The inner integrals' errors are integrated
/// over the outer variable (a midpoint sum over every outer node evaluated: tanh_sinh's nodes
/// crowd where its panels end, so one poor inner integral next to a cut weighs what its width
/// does, not the whole span, as nested() charges).
template <class F>
Value nested_tanh_sinh(F&& point, const std::vector<double>& outer_cut, const std::vector<double>& inner_cut,
                       const Options& options) {
  Value out;
  const double inner_absolute = inner_tolerance(point, outer_cut, inner_cut, options);
  std::vector<std::pair<double, double>> inner_errors;  // (outer node, inner error there)
  auto inner = [&](double x) {
    double error = 0.0;
    const double value =
        tanh_sinh_panels([&](double y) { return point(x, y); }, inner_cut, options, inner_absolute, &error);
    inner_errors.push_back({x, error});
    return value;
  };
  out.value = tanh_sinh_panels(inner, outer_cut, options, 0.5 * options.absolute_tolerance, &out.error);
  std::sort(inner_errors.begin(), inner_errors.end());
  for (std::size_t k = 0; k < inner_errors.size(); ++k) {
    const double left = k == 0 ? outer_cut.front() : 0.5 * (inner_errors[k - 1].first + inner_errors[k].first);
    const double right =
        k + 1 == inner_errors.size() ? outer_cut.back() : 0.5 * (inner_errors[k].first + inner_errors[k + 1].first);
    out.inner_error += inner_errors[k].second * (right - left);
  }
  return out;
}

/// integrate(count), where count() is called once per evaluation of f: the Value it returns with its
/// evaluations counted, or the unresolved Value (0 ± inf) when they pass `max_evaluations` or when
/// tanh_sinh refuses a non-finite value at a node.
template <class Integrate>
Value within_budget(long long max_evaluations, Integrate&& integrate) {
  struct OutOfBudget {};
  long long evaluations = 0;
  const auto count = [&] {
    if (++evaluations > max_evaluations) throw OutOfBudget{};
  };
  try {
    Value out = integrate(count);
    out.evaluations = evaluations;
    return out;
  } catch (const OutOfBudget&) {
  } catch (const boost::math::evaluation_error&) {}
  return {0.0, std::numeric_limits<double>::infinity(), 0.0, evaluations, false};
}

}  // namespace

Value lune_integral(const std::function<double(const Vec3&)>& f, const LuneCoordinates& lune,
                    const std::vector<double>& t_cuts, const std::vector<double>& psi_cuts, const Options& options) {
  if (lune.empty) return {};
  return within_budget(options.max_evaluations, [&](const auto& count) {
    auto point = [&](double t, double psi) {
      count();
      const Vec3 k = lune.direction(t, psi);
      return std::cos(t) * std::max(k.z, 0.0) * f(k);
    };
    return options.tanh_sinh ? nested_tanh_sinh(point, t_cuts, psi_cuts, options)
           : options.swapped
               ? nested<31>([&](double psi, double t) { return point(t, psi); }, psi_cuts, t_cuts, options)
               : nested<61>(point, t_cuts, psi_cuts, options);
  });
}

namespace {

/// Break points of the law's integrand over k with `fixed` held: the mirror of fixed and fixed
/// itself (K&P's lobes), and with options.use_mass_hints every peak of the model's hints with
/// lines at ±1 and ±2 of its widths, and its horizon layer at delta and 4 delta from the horizon.
std::pair<std::vector<double>, std::vector<double>> break_points(const Model& model, const LuneCoordinates& lune,
                                                                 const Vec3& fixed, Varying varying,
                                                                 const Options& options) {
  std::vector<double> t_centres, psi_centres;
  for (const Vec3& peak : {mirror(fixed), fixed}) {
    const auto [t, psi] = lune.coordinates(peak);
    t_centres.push_back(t);
    psi_centres.push_back(psi);
  }
  std::vector<double> t_cut = cuts(-pi / 2, pi / 2, t_centres), psi_cut = cuts(lune.psi_lo, lune.psi_hi, psi_centres);
  if (!options.use_mass_hints) return {t_cut, psi_cut};
  const MassHints hints = model.mass_hints(fixed, varying);
  // Inside the range only; its ends are fixed now (cut.back() moves as cuts are appended).
  const std::pair<double, double> t_range{t_cut.front(), t_cut.back()}, psi_range{psi_cut.front(), psi_cut.back()};
  auto add = [&](std::vector<double>& cut, double x) {
    const auto [lo, hi] = &cut == &t_cut ? t_range : psi_range;
    if (x > lo && x < hi) cut.push_back(x);
  };
  // Creases on half great circles through ±crease_axis (MassHints): when the lune's edge axis is
  // crease_axis (the hemisphere_edge below chooses it) they are the lines psi = longitude, cut exactly.
  if (glm::dot(lune.e, hints.crease_axis) > 1.0 - 1e-12)
    for (double longitude : hints.crease_longitudes) add(psi_cut, longitude);
  for (const Peak& peak : hints.peaks) {
    const auto [t, psi] = lune.coordinates(peak.direction);
    for (double w : {peak.width, peak.across > 0.0 ? peak.across : peak.width})
      for (double m : {-2.0, -1.0, 0.0, 1.0, 2.0}) add(t_cut, t + m * w), add(psi_cut, psi + m * w);
  }
  for (double m : {1.0, 4.0}) {
    const double delta = m * hints.horizon_layer;
    if (delta <= 0.0) continue;
    add(t_cut, -pi / 2 + delta), add(t_cut, pi / 2 - delta), add(psi_cut, pi / 2 - delta);
    if (lune.psi_lo == -pi / 2) add(psi_cut, -pi / 2 + delta);
  }
  for (auto* cut : {&t_cut, &psi_cut}) {
    std::sort(cut->begin(), cut->end());
    cut->erase(std::unique(cut->begin(), cut->end(), [](double a, double b) { return b - a < 1e-12; }), cut->end());
  }
  return {t_cut, psi_cut};
}

}  // namespace

namespace {

/// ∫ (k·n) f(k) dk over the domain of `coords`, nested tanh_sinh: beta outer over `beta_cut`, the
/// ray's radii inner, mapped onto w ∈ [0, 1] (r = lo + w (hi - lo)), whose nodes crowd towards the
/// ray's entry into the domain. Along a ray |k + fixed| = 2 sin(r/2), so a microfacet integrand's
/// 1/|k + fixed| is cancelled by the Jacobian's sin r; p itself lies lo before w = 0 (outside the
/// domain when fixed is above the horizon).
Value antipode_integral(const std::function<double(const Vec3&)>& f, const AntipodeCoordinates& coords,
                        const std::vector<double>& beta_cut, const Options& options) {
  if (coords.empty) return {};
  // Panels of w graded towards the domain's entry (w = 4^-20 ... 1/4): a microfacet model's
  // shadowing turns at |k + fixed| ~ 4 (fixed·n) and k·n = fixed·n, scales down to 1e-9 there.
  std::vector<double> w_cut{0.0};
  for (int m = 20; m >= 0; --m) w_cut.push_back(std::ldexp(1.0, -2 * m));
  return within_budget(options.max_evaluations, [&](const auto& count) {
    auto point = [&](double beta, double w) {
      count();
      const auto [lo, hi] = coords.radii(beta);
      if (lo >= hi) return 0.0;
      const double r = lo + w * (hi - lo);
      const Vec3 k = coords.direction(r, beta);
      return (hi - lo) * std::sin(r) * std::max(k.z, 0.0) * f(k);
    };
    return nested_tanh_sinh(point, beta_cut, w_cut, options);
  });
}

/// Cuts of beta: the rays along the horizon and along the pole's great circle (where the ray's
/// entry into the domain swings from r ≈ 0 to r ≈ pi when p is near them), the rays through the
/// lune's tips (where the bounding circle changes), and the rays through the mirror of `fixed`
/// and, with options.use_mass_hints, through every peak of the hints at ±1 and ±2 of its width
/// (taken as beta offsets, unscaled by the peak's distance from p; the hints' creases are not cut:
/// this reference is a witness, reports/extremes.h).
std::vector<double> antipode_cuts(const Model& model, const AntipodeCoordinates& coords, const Vec3& fixed,
                                  Varying varying, const Options& options) {
  std::vector<double> centres{pi / 2, -pi / 2, coords.beta(mirror(fixed))};
  const double pole_beta = std::atan2(-glm::dot(coords.u, coords.pole), glm::dot(coords.v, coords.pole));
  centres.insert(centres.end(), {pole_beta, pole_beta > 0 ? pole_beta - pi : pole_beta + pi});
  const Vec3 edge = glm::cross(coords.n, coords.pole);
  if (glm::length(edge) > 1e-12) centres.insert(centres.end(), {coords.beta(edge), coords.beta(-edge)});
  std::vector<double> cut{-pi, pi};
  for (double c : centres)
    if (c > -pi && c < pi) cut.push_back(c);
  if (options.use_mass_hints)
    for (const Peak& peak : model.mass_hints(fixed, varying).peaks)
      for (double m : {-2.0, -1.0, 0.0, 1.0, 2.0}) {
        const double c = coords.beta(peak.direction) + m * peak.width;
        if (c > -pi && c < pi) cut.push_back(c);
      }
  std::sort(cut.begin(), cut.end());
  cut.erase(std::unique(cut.begin(), cut.end(), [](double a, double b) { return b - a < 1e-12; }), cut.end());
  return cut;
}

}  // namespace

/// The hemisphere's edge axis for an integrand whose lobes lie about `fixed` and its mirror:
/// kHemisphereEdge, unless a lobe lies within kPoleClearance of that axis (a grazing direction in
/// the xz-plane), where the psi lines converge and no nested rule resolves it: then the axis across
/// the plane of `fixed` and n, which puts both lobes at t = 0. A model with creases keeps its crease
/// axis (they are coordinate lines about it).
constexpr double kPoleClearance = 0.1;
Vec3 hemisphere_edge(const Model& model, const Vec3& fixed, Varying varying) {
  const Vec3 crease_axis = model.mass_hints(fixed, varying).crease_axis;
  if (glm::length(crease_axis) > 0.0) return glm::normalize(crease_axis);
  // fixed and its mirror (-x, -y, z) are equally far from the axis ±x
  if (std::abs(glm::dot(fixed, kHemisphereEdge)) < std::cos(kPoleClearance)) return kHemisphereEdge;
  return glm::normalize(glm::cross(kNormal, fixed));
}

Value vignetting(const Model& model, const Vec3& i, const Vec3& j, const Options& options) {
  if (options.about_antipode) {
    const AntipodeCoordinates coords(i, j);
    return antipode_integral([&](const Vec3& k) { return model.f(k, j); }, coords,
                             antipode_cuts(model, coords, j, Varying::incident, options), options);
  }
  const LuneCoordinates lune(i, hemisphere_edge(model, j, Varying::incident));
  if (lune.empty) return {};
  const auto [t_cut, psi_cut] = break_points(model, lune, j, Varying::incident, options);
  return lune_integral([&](const Vec3& k) { return model.f(k, j); }, lune, t_cut, psi_cut, options);
}

Value darkening(const Model& model, const Vec3& j, const Options& options) {
  return vignetting(model, kNormal, j, options);
}

Value albedo(const Model& model, const Vec3& i, const Options& options) {
  if (options.about_antipode) {
    const AntipodeCoordinates coords(kNormal, i);
    return antipode_integral([&](const Vec3& k) { return model.f(i, k); }, coords,
                             antipode_cuts(model, coords, i, Varying::outgoing, options), options);
  }
  const LuneCoordinates lune(kNormal, hemisphere_edge(model, i, Varying::outgoing));
  const auto [t_cut, psi_cut] = break_points(model, lune, i, Varying::outgoing, options);
  return lune_integral([&](const Vec3& k) { return model.f(i, k); }, lune, t_cut, psi_cut, options);
}

}  // namespace ganzfeld::reference
