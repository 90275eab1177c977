// Poulin & Fournier 1990, additive cylinders: formulas, sources and the derivation of the
// creases are in models/poulin_fournier.h.
#include "models/poulin_fournier.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <boost/math/special_functions/beta.hpp>

#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

// Boost policy that never throws (f is noexcept; errors give NaN/0, handled by the callers) and
// computes in double (promotion to long double costs 10x here; accuracy measured in the tests).
using NoThrow =
    boost::math::policies::policy<boost::math::policies::promote_double<false>,
                                  boost::math::policies::domain_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::pole_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::overflow_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::evaluation_error<boost::math::policies::errno_on_error>>;

/// A root beta of the crease equations is accepted when the function it was solved for agrees
/// with the target to this (radians or floor lengths, O(1) quantities).
constexpr double kRootCheck = 1e-9;

/// Roots in (0, pi/2] of a sin(beta) + b cos(beta) = 1: R sin(beta + gamma) = 1 with
/// R = |(a, b)|, gamma = atan2(b, a).
std::vector<double> sin_cos_roots(double a, double b) {
  const double R = std::hypot(a, b);
  if (!(R >= 1.0)) return {};
  const double gamma = std::atan2(b, a), s = std::asin(1.0 / R);
  std::vector<double> roots;
  for (double beta : {s - gamma, pi - s - gamma, s - gamma + 2 * pi, pi - s - gamma - 2 * pi})
    if (beta > 0.0 && beta <= pi / 2) roots.push_back(beta);
  return roots;
}

/// ∫_0^tau cos^m for tau in [0, pi/2].
double cos_power_head(double m, double tau) noexcept {
  const double s = std::sin(tau);
  return 0.5 * boost::math::beta(0.5, 0.5 * (m + 1.0), s * s, NoThrow());
}
/// ∫_tau^{pi/2} cos^m for tau in [0, pi/2].
double cos_power_tail(double m, double tau) noexcept {
  const double c = std::cos(tau);
  return 0.5 * boost::math::beta(0.5 * (m + 1.0), 0.5, c * c, NoThrow());
}

}  // namespace

// ---------------------------------------------------------------------------------------------
double cos_power_integral(double m, double t_a, double t_b) noexcept {
  t_a = std::clamp(t_a, -pi / 2, pi / 2);
  t_b = std::clamp(t_b, -pi / 2, pi / 2);
  if (!(t_b > t_a)) return 0.0;
  double value;
  if (t_a < 0.0 && t_b > 0.0) {
    value = cos_power_head(m, -t_a) + cos_power_head(m, t_b);
  } else {
    const double lo = t_a >= 0.0 ? t_a : -t_b, hi = t_a >= 0.0 ? t_b : -t_a;  // 0 <= lo < hi
    // Below about the median of cos^m (Gaussian ~ exp(-m t^2/2): 0.67/sqrt(m)) the heads are
    // small and their difference accurate; above it, the tails.
    const double split = std::min(0.6745 / std::sqrt(std::max(m, 1.0)), pi / 4);
    value = hi <= split ? cos_power_head(m, hi) - cos_power_head(m, lo) : cos_power_tail(m, lo) - cos_power_tail(m, hi);
  }
  return std::isfinite(value) && value > 0.0 ? value : 0.0;
}

double integral_sin_squared(double x) noexcept {
  // (x - sin x cos x)/2 = (y - sin y)/4 with y = 2x; for |y| < 1 the series
  // y - sin y = y^3 sum_k (-1)^k y^{2k}/(2k+3)!, to k = 7 (next term < 1e-17 relative).
  const double y = 2.0 * std::abs(x);
  double v;
  if (y < 1.0) {
    const double y2 = y * y;
    constexpr double inv_fact[8] = {
        1.0 / 6,        1.0 / 120,        1.0 / 5040,          1.0 / 362880,
        1.0 / 39916800, 1.0 / 6227020800, 1.0 / 1307674368000, 1.0 / 355687428096000};  // 1/(2k+3)!
    double sum = 0.0;
    for (int k = 7; k >= 0; --k) sum = (k % 2 ? -inv_fact[k] : inv_fact[k]) + y2 * sum;
    v = y * y2 * sum / 4.0;
  } else {
    v = (y - std::sin(y)) / 4.0;
  }
  return x < 0.0 ? -v : v;
}

// ---------------------------------------------------------------------------------------------
PoulinFournier::PoulinFournier(double kd, double ks, double n, double d, double h)
    : kd_(kd), ks_(ks), n_(n), d_(d), h_(h), C_(blinn_phong_normalization(n)), local_(kd, ks, n) {
  const double phi_h = std::acos(std::clamp(h, 0.0, 1.0));
  const double phi_d = d < 2.0 ? std::asin(0.5 * d) : pi / 2;
  theta_M_ = std::min(phi_d, phi_h);  // app. D
  floor_w_ = std::max(d - 2.0 * std::sqrt(std::max(0.0, (1.0 - h) * (1.0 + h))), 0.0);
}

std::string PoulinFournier::spec() const {
  return spec_text({"poulin-fournier", {{"kd", kd_}, {"ks", ks_}, {"n", n_}, {"d", d_}, {"h", h_}}});
}

PfProjection PoulinFournier::project(const Vec3& k) const noexcept {
  PfProjection p;
  p.side = k.y >= 0.0 ? 1 : -1;
  p.beta = std::clamp(std::atan2(std::max(k.z, 0.0), std::abs(k.y)), kGrazingCosFloor, pi / 2);
  return p;
}

double PoulinFournier::neighbour_limit(double beta) const noexcept {
  // theta_s = theta_L + asin(d cos theta_L - 1), theta_L = pi/2 - beta; with
  // asin(x - 1) = -pi/2 + 2 asin(sqrt(x/2)): theta_s = 2 asin(sqrt(d sin(beta)/2)) - beta.
  // "if 1/cos theta_L < d - 1, theta_s = pi/2" (app. D) is exactly theta_s >= pi/2.
  const double sb = std::sin(beta);
  if ((d_ - 1.0) * sb > 1.0) return pi / 2;
  return 2.0 * std::asin(std::min(1.0, std::sqrt(0.5 * d_ * sb))) - beta;
}

double PoulinFournier::floor_blocked(double beta) const noexcept {
  if (!(floor_w_ > 0.0) || beta >= theta_M_) return 0.0;
  // 1/cos theta_L - sqrt(1 - h^2) - h tan theta_L = (1 - sin(phi_h + theta_L))/cos theta_L
  //   = (1 - cos(beta - phi_h))/sin beta, and theta_M = phi_h when there is a floor.
  const double s = std::sin(0.5 * (beta - theta_M_));
  return std::min(2.0 * s * s / std::sin(beta), floor_w_);
}

PfFront PoulinFournier::front(const PfProjection& p) const noexcept {
  if (p.beta >= theta_M_) return {-theta_M_, theta_M_, 0.0, floor_w_};
  const double near = std::min(neighbour_limit(p.beta), theta_M_);  // the neighbour's shadow
  const double far = p.beta;                                        // the terminator
  const double blocked = floor_blocked(p.beta);
  if (p.side > 0) return {-far, near, 0.0, floor_w_ - blocked};
  return {-near, far, blocked, floor_w_};
}

double PoulinFournier::arc_cosine_product(const PfProjection& pi_, const PfProjection& pj, double a,
                                          double b) const noexcept {
  if (!(b > a)) return 0.0;
  // sin(u_i) sin(u_j), u_k = s_k psi + beta_k, as sin^2(X) - sin^2(c) (same side) or
  // sin^2(c) - sin^2(X) (opposite sides), X linear in psi with slope +-1: no cancellation of
  // large terms when the arc is short and the directions graze.
  double value;
  if (pi_.side == pj.side) {
    const double s = pi_.side, mid = 0.5 * (pi_.beta + pj.beta), half = std::sin(0.5 * (pi_.beta - pj.beta));
    const double sq = std::abs(integral_sin_squared(s * b + mid) - integral_sin_squared(s * a + mid));
    value = sq - half * half * (b - a);
  } else {
    const double s = pi_.side, off = 0.5 * (pi_.beta - pj.beta), sum = std::sin(0.5 * (pi_.beta + pj.beta));
    const double sq = std::abs(integral_sin_squared(s * b + off) - integral_sin_squared(s * a + off));
    value = sum * sum * (b - a) - sq;
  }
  value /= std::sin(pi_.beta) * std::sin(pj.beta);
  return std::isfinite(value) && value > 0.0 ? value : 0.0;
}

double PoulinFournier::arc_specular(const PfProjection& pi_, const PfProjection& pj, double a, double b,
                                    const Vec3& h) const noexcept {
  if (!(b > a)) return 0.0;
  const double r_h = std::hypot(h.y, h.z);
  const double rn = std::pow(std::min(r_h, 1.0), n_);  // N.h = r_h cos(psi - theta_H)
  if (!(rn > 0.0)) return 0.0;
  const double theta_H = std::atan2(h.y, h.z);
  // sin(u_i) sin(u_j) = P0 + P1 cos 2psi + P2 sin 2psi.
  double P0, P1, P2;
  if (pi_.side == pj.side) {
    const double S = pi_.beta + pj.beta;
    P0 = 0.5 * std::cos(pi_.beta - pj.beta);
    P1 = -0.5 * std::cos(S);
    P2 = 0.5 * pi_.side * std::sin(S);
  } else {
    const double D = pi_.beta - pj.beta;
    P0 = -0.5 * std::cos(pi_.beta + pj.beta);
    P1 = 0.5 * std::cos(D);
    P2 = -0.5 * pi_.side * std::sin(D);
  }
  // In t = psi - theta_H: A + B cos 2t + C sin 2t.
  const double c2 = std::cos(2.0 * theta_H), s2 = std::sin(2.0 * theta_H);
  const double A = P0, B = P1 * c2 + P2 * s2, C = P2 * c2 - P1 * s2;
  // On the arc N.i, N.j >= 0, so N.h >= 0: t stays in [-pi/2, pi/2] (clamped against rounding).
  const double ta = std::clamp(a - theta_H, -pi / 2, pi / 2), tb = std::clamp(b - theta_H, -pi / 2, pi / 2);
  // ∫ cos^n t (A + B (2 cos^2 t - 1) + 2 C sin t cos t) dt, with
  // I_{n+2} = [cos^{n+1} t sin t]/(n+2) + (n+1)/(n+2) I_n (integration by parts).
  const double cos_a = std::cos(ta), cos_b = std::cos(tb);
  const double pow_a = std::pow(cos_a, n_ + 1.0), pow_b = std::pow(cos_b, n_ + 1.0);
  const double In = cos_power_integral(n_, ta, tb);
  const double In2 = ((pow_b * std::sin(tb) - pow_a * std::sin(ta)) + (n_ + 1.0) * In) / (n_ + 2.0);
  const double tail = 2.0 / (n_ + 2.0) * (pow_a * cos_a - pow_b * cos_b);
  const double value = rn * ((A - B) * In + 2.0 * B * In2 + C * tail) / (std::sin(pi_.beta) * std::sin(pj.beta));
  return std::isfinite(value) && value > 0.0 ? value : 0.0;
}

double PoulinFournier::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double flat = local_.f(i, j);
  if (!(theta_M_ > 0.0)) return flat;  // d = 0 or h = 1: a plane
  const PfProjection pi_ = project(i), pj = project(j);
  const PfFront fi = front(pi_), fj = front(pj);
  const double a = std::max(fi.arc_lo, fj.arc_lo), b = std::min(fi.arc_hi, fj.arc_hi);
  const double floor_vi = std::max(0.0, std::min(fi.floor_hi, fj.floor_hi) - std::max(fi.floor_lo, fj.floor_lo));
  double arc = 0.0;
  if (b > a) {
    if (kd_ > 0.0) arc += kd_ / pi * arc_cosine_product(pi_, pj, a, b);
    const Vec3 sum = i + j;
    const double len = glm::length(sum);
    if (ks_ > 0.0 && len > 0.0) arc += ks_ * C_ * arc_specular(pi_, pj, a, b, sum / len);
  }
  const double value = (arc + floor_vi * flat) / d_;  // eq. III.21 with l_v + f_v = d
  return std::isfinite(value) && value > 0.0 ? value : 0.0;
}

std::optional<GlslF> PoulinFournier::glsl_f() const {
  // As f(): the local blinn-phong (BlinnPhong::glsl_f's form), then the fronts of i and j, their
  // intersection on the arc and on the floor, the arc integrals (models/glsl.cpp, gz_pf).
  const std::string flat =
      "  vec3 s = i + j;\n"
      "  float len = length(s);\n"
      "  float flat_f = " +
      decimal_literal(kd_ / pi) +
      ";\n"
      "  if (len > 0.0) flat_f += " +
      decimal_literal(ks_ * C_) + " * gz_pow_pair(s.z / len, dot(s.xy, s.xy) / (len * (len + s.z)), " +
      decimal_literal(n_) + ");\n";
  if (!(theta_M_ > 0.0)) return GlslF{std::string(kGlslBelowHorizon) + flat + "  return flat_f;\n", {"gz_pow_pair"}};
  const std::string d = decimal_literal(d_), theta_M = decimal_literal(theta_M_), w = decimal_literal(floor_w_);
  return GlslF{
      std::string(kGlslBelowHorizon) + flat +
          "  vec2 pi_ = gz_pf_project(i), pj = gz_pf_project(j);\n"
          "  vec4 fi = gz_pf_front(pi_, " +
          d + ", " + theta_M + ", " + w + "), fj = gz_pf_front(pj, " + d + ", " + theta_M + ", " + w +
          ");\n"
          "  float a = max(fi.x, fj.x), b = min(fi.y, fj.y);\n"
          "  float floor_vi = max(0.0, min(fi.w, fj.w) - max(fi.z, fj.z));\n"
          "  float arc = 0.0;\n"
          "  if (b > a) {\n" +
          (kd_ > 0.0 ? "    arc += " + decimal_literal(kd_ / pi) + " * gz_pf_arc_cosine_product(pi_, pj, a, b);\n"
                     : "") +
          (ks_ > 0.0 ? "    if (len > 0.0) arc += " + decimal_literal(ks_ * C_) +
                           " * gz_pf_arc_specular(pi_, pj, a, b, s / len, " + decimal_literal(n_) + ");\n"
                     : "") +
          "  }\n"
          "  float value = (arc + floor_vi * flat_f) * " +
          decimal_literal(1.0 / d_) +
          ";\n"
          "  return isinf(value) || isnan(value) || !(value > 0.0) ? 0.0 : value;\n",
      {"gz_pow_pair", "gz_pf"},
      0.0,
      true};
}

// ---------------------------------------------------------------------------------------------
std::vector<PfCrease> PoulinFournier::creases(const Vec3& fixed) const {
  std::vector<PfCrease> out;
  if (!(theta_M_ > 0.0)) return out;
  // The varying direction k at elevation beta on side s has longitude phi = -theta_k = -s (pi/2 - beta).
  auto add = [&](int s, double beta, bool kink) {
    if (beta > kGrazingCosFloor && beta <= theta_M_) out.push_back({-s * (pi / 2 - beta), kink});
  };
  // theta_s(beta) = c  <=>  (d - sin c) sin beta + cos c cos beta = 1 (from d sin(beta)/2 = sin^2((c + beta)/2)).
  auto neighbour_roots = [&](double c) {
    std::vector<double> roots;
    for (double beta : sin_cos_roots(d_ - std::sin(c), std::cos(c)))
      if (beta < theta_M_ && std::abs(neighbour_limit(beta) - c) <= kRootCheck) roots.push_back(beta);
    return roots;
  };
  // f_s(beta) = g  <=>  (g + sin theta_M) sin beta + cos theta_M cos beta = 1.
  auto floor_roots = [&](double g) {
    std::vector<double> roots;
    if (!(g > 0.0 && g < floor_w_)) return roots;
    for (double beta : sin_cos_roots(g + std::sin(theta_M_), std::cos(theta_M_)))
      if (beta < theta_M_ && std::abs(floor_blocked(beta) - g) <= kRootCheck) roots.push_back(beta);
    return roots;
  };

  const PfProjection pf = project(fixed);
  const PfFront ff = front(pf);
  // Which ends of the period the fixed direction reaches: the end of the arc at -theta_M and the
  // floor next to it at t = w ("left"), or those at +theta_M and t = 0 ("right").
  const bool sees_left = ff.arc_lo == -theta_M_ || (ff.floor_hi == floor_w_ && ff.floor_lo < floor_w_);
  const bool sees_right = ff.arc_hi == theta_M_ || (ff.floor_lo == 0.0 && ff.floor_hi > 0.0);

  // Of k alone, where the fixed direction reaches. The terminator of k (s = +1) reaches the arc's
  // end at -theta_M, and the shadow of the cylinder on its side starts on the floor at t = w: C1
  // only (the integrand vanishes at a terminator; f_s and theta_M - theta_s grow quadratically).
  // The neighbour's shadow reaches the arc at +theta_M as the floor lit from t = 0 shrinks to
  // nothing: a kink. (Mirror for s = -1.)
  if (sees_left) add(1, theta_M_, false);
  if (sees_right) add(-1, theta_M_, false);
  if (floor_w_ > 0.0)
    for (double beta : neighbour_roots(theta_M_)) {
      if (sees_right) add(1, beta, true);
      if (sees_left) add(-1, beta, true);
    }

  // Of k against the fixed front: an end of the intersection switches from one direction's limit
  // to the other's. A kink unless one of the two limits is a terminator (integrand 0 there: C1).
  const double c_lo = -ff.arc_lo, c_hi = ff.arc_hi;                           // in (0, theta_M]
  const bool lo_is_terminator = pf.side > 0, hi_is_terminator = pf.side < 0;  // when limited
  if (c_lo < theta_M_) {
    add(1, c_lo, false);                                                         // k's terminator (s = +1)
    for (double beta : neighbour_roots(c_lo)) add(-1, beta, !lo_is_terminator);  // k's neighbour limit (s = -1)
  }
  if (c_hi < theta_M_) {
    add(-1, c_hi, false);
    for (double beta : neighbour_roots(c_hi)) add(1, beta, !hi_is_terminator);
  }
  if (floor_w_ > 0.0) {
    // s = +1 lights/sees [0, w - f_s]; s = -1 [f_s, w]: every switch of the overlap is a kink.
    for (double g : {floor_w_ - ff.floor_lo, floor_w_ - ff.floor_hi})
      for (double beta : floor_roots(g)) add(1, beta, true);
    for (double g : {ff.floor_lo, ff.floor_hi})
      for (double beta : floor_roots(g)) add(-1, beta, true);
  }
  std::sort(out.begin(), out.end(), [](const PfCrease& x, const PfCrease& y) { return x.longitude < y.longitude; });
  std::vector<PfCrease> unique;
  for (const PfCrease& c : out) {
    if (!unique.empty() && c.longitude - unique.back().longitude <= 1e-12)
      unique.back().kink = unique.back().kink || c.kink;
    else unique.push_back(c);
  }
  return unique;
}

std::vector<double> PoulinFournier::crease_longitudes(const Vec3& fixed) const {
  std::vector<double> phis;
  for (const PfCrease& c : creases(fixed)) phis.push_back(c.longitude);
  return phis;
}

MassHints PoulinFournier::mass_hints(const Vec3& fixed, Varying) const {
  HintBuilder hints;
  hints.creases(theta_M_ > 0.0 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 0.0, 0.0}, crease_longitudes(fixed));
  if (ks_ > 0.0) {
    // (N.h)^n about the mirror of `fixed` in N(psi), width 2/sqrt(n) as blinn-phong; psi spans
    // the arc, so the highlight is a band (the cone j_x = -i_x): five points along it. Across the
    // plane of N and `fixed` the halfway lobe is (fixed·N) times thinner, floored at 1e-3, as
    // blinn-phong's (models/classic.cpp), so that d = 0 (a plane) is honest in the thin lune of g
    // with the view on the horizon opposite (tests/extremes_test.cpp, PoulinFournierPlaneConeIsHonest).
    const double width = 2.0 / std::sqrt(n_);
    const int count = theta_M_ > 0.0 ? 5 : 1;
    for (int m = 0; m < count; ++m) {
      const double psi = count > 1 ? theta_M_ * (0.5 * m - 1.0) : 0.0;
      const Vec3 N{0.0, std::sin(psi), std::cos(psi)};
      // Declared only where the lobe is at least twice thinner across: an across width close to
      // the along one adds nothing but cut lines a sliver apart (the reference then bisects the
      // slivers next to the creases until its budget runs out: h at j = n).
      const double height = glm::dot(N, fixed), across = width * std::max(height, 1e-3);
      hints.lobe(2.0 * height * N - fixed, width, across < 0.5 * width ? across : 0.0);
    }
  }
  return hints.build();
}

// ---------------------------------------------------------------------------------------------
void register_poulin_fournier_models(std::vector<ModelInfo>& c) {
  c.push_back(
      {"poulin-fournier",
       "additive cylinders along the tangent (x), radius 1, spacing d, floor at height h, shadowing and masking "
       "in the cross-section; local blinn-phong on the arcs and the floor (anisotropic)",
       "Poulin & Fournier 1990, SIGGRAPH '90 (Computer Graphics 24(4) 273-282); Walker 1999, MSc thesis "
       "(U. Oregon), ch. III Poulin-Fournier (eqs. III.19-III.21), app. D",
       {kd_param(0.5),
        ks_param(0.3),
        n_param(20.0, "exponent of N.h on the cylinders and the floor"),
        {"d", ParamType::real, 0.0, 100.0, 2.5, "distance between cylinder axes, in cylinder radii (0: a plane)"},
        {"h", ParamType::real, 0.0, 1.0, 0.2, "height of the floor above the axes, in radii (1: a plane)"}},
       {false, true, EnergyClass::plausible},
       {},
       [](const ParamValues& p) -> ModelPtr {
         require_sum_at_most_one("poulin-fournier", "kd", p.at("kd"), "ks", p.at("ks"));
         return std::make_shared<PoulinFournier>(p.at("kd"), p.at("ks"), p.at("n"), p.at("d"), p.at("h"));
       }});
}

}  // namespace ganzfeld
