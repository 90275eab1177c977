// He, Torrance, Sillion & Greenberg 1991, unpolarized: formulas, equation numbers and the
// choices made where the printed equations are ambiguous are in models/he_torrance.h.
#include "models/he_torrance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/special_functions/gamma.hpp>

#include "models/classic_models.h"  // fresnel_complex
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

// Boost policy that never throws (f is noexcept); errors give NaN/0, handled by the callers.
using NoThrow =
    boost::math::policies::policy<boost::math::policies::domain_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::pole_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::overflow_error<boost::math::policies::errno_on_error>,
                                  boost::math::policies::evaluation_error<boost::math::policies::errno_on_error>>;

/// Below this an absolute tail is irrelevant whatever the partial sum (smallest normal double).
constexpr double kTiny = std::numeric_limits<double>::min();
/// Re-anchor the Poisson-weight recurrence this often (its rounding drifts ~1 ulp per step).
constexpr int kReanchor = 256;
/// a = tau cot theta / (2 sigma0) beyond which erfc(a) and exp(-a^2) vanish in double: S = 1.
constexpr double kShadowFree = 27.0;

/// e^{-c/m}/m.
inline double h_of(double m, double c) noexcept { return std::exp(-c / m) / m; }
/// max of e^{-c/x}/x over x in [lo, hi] (hi may be +inf): it increases below x = c and
/// decreases above, so the maximum is at c clamped into the interval.
inline double h_max(double lo, double hi, double c) noexcept { return h_of(std::clamp(c, lo, hi), c); }

/// e^{-g} g^{m-1}/m! (the Poisson weight p_m divided by g), m >= 1, g > 0.
double q_exact(double m, double g) noexcept {
  if (m == 1.0) return std::exp(-g);
  return boost::math::gamma_p_derivative(m + 1.0, g, NoThrow()) / g;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
double he_series_over_g(double g, double c, double rel_tol, int* terms) noexcept {
  if (terms) *terms = 0;
  if (!(c >= 0.0)) c = 0.0;
  if (!(g > 0.0)) {  // g = 0: only m = 1 survives, e^{-0} g^0/1! e^{-c}/1
    if (terms) *terms = 1;
    return std::exp(-c);
  }
  if (!std::isfinite(g)) return 0.0;
  const double half_tol = 0.5 * std::max(rel_tol, 0.0);
  const double m0 = std::max(1.0, std::floor(g));  // mode of the Poisson weights
  double sum = 0.0;
  int n = 0;

  // Upwards, m = m0, m0+1, ...: after adding term m, the rest is
  //   sum_{m'>m} q_m' h_m' <= q_{m+1} / (1 - g/(m+2)) * max_{x>=m+1} h(x)
  // since q_{m'+1}/q_m' = g/(m'+1) <= g/(m+2) < 1 for m' >= m+1 (m >= m0 >= g-1).
  double m = m0, q = q_exact(m0, g);
  for (;;) {
    sum += q * h_of(m, c);
    ++n;
    const double q_next = q * g / (m + 1.0);
    const double tail = q_next / (1.0 - g / (m + 2.0)) * h_max(m + 1.0, std::numeric_limits<double>::infinity(), c);
    if (!(tail > half_tol * sum) || tail < kTiny) break;
    m += 1.0;
    q = (n % kReanchor == 0) ? q_exact(m, g) : q_next;
  }

  // Downwards, m = m0-1, ..., 1: before adding term m, the rest (m' <= m) is
  //   sum_{m'<=m} q_m' h_m' <= q_m / (1 - m/g) * max_{1<=x<=m} h(x)
  // since q_{m'-1}/q_m' = m'/g <= m/g < 1 (m <= m0 - 1 <= g - 1).
  m = m0 - 1.0;
  q = q_exact(m0, g) * m0 / g;
  int down = 0;
  while (m >= 1.0) {
    const double tail = q / (1.0 - m / g) * h_max(1.0, m, c);
    if (!(tail > half_tol * sum) || tail < kTiny) break;
    sum += q * h_of(m, c);
    ++n;
    ++down;
    q = (down % kReanchor == 0) ? q_exact(m - 1.0, g) : q * m / g;
    m -= 1.0;
  }
  if (terms) *terms = n;
  return sum;
}

double he_series(double g, double c, double rel_tol, int* terms) noexcept {
  if (!(g > 0.0)) {
    if (terms) *terms = 0;
    return 0.0;
  }
  return g * he_series_over_g(g, c, rel_tol, terms);
}

double he_z0_over_sigma0(double f0) noexcept {
  if (!(f0 > 0.0)) return 0.0;
  if (std::isinf(f0)) return std::numeric_limits<double>::infinity();
  // psi(x) = ln x + x^2/2 - ln f0 is increasing; its root is the root of x e^{x^2/2} = f0.
  const double L = std::log(f0);
  double lo, hi, x;
  if (f0 <= 1.0) {  // x <= f0 (e^{x^2/2} >= 1) and x >= f0 e^{-1/2} (x <= 1)
    lo = f0 * std::exp(-0.5);
    hi = f0;
    x = f0;
  } else {  // x >= sqrt(ln f0) (x <= e^{x^2/2}); x <= sqrt(2 ln f0) when x >= 1
    lo = std::sqrt(L);
    hi = std::max(1.0, std::sqrt(2.0 * L));
    x = std::clamp(std::sqrt(2.0 * L), lo, hi);
  }
  for (int it = 0; it < 200; ++it) {
    const double psi = std::log(x) + 0.5 * x * x - L;
    if (psi == 0.0) return x;
    if (psi > 0.0) hi = x;
    else lo = x;
    double next = x - psi / (1.0 / x + x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (std::abs(next - x) <= 2.0 * std::numeric_limits<double>::epsilon() * x) return next;
    x = next;
  }
  return x;
}

// ---------------------------------------------------------------------------------------------
HeTorrance::HeTorrance(double sigma0, double tau, double lambda, double eta, double k, double a)
    : sigma0_(sigma0),
      tau_(tau),
      lambda_(lambda),
      eta_(eta),
      k_(k),
      a_(a),
      prefactor_(pi * pi * tau * tau / (4.0 * lambda * lambda)),
      c_scale_((pi * tau / lambda) * (pi * tau / lambda)) {}

std::string HeTorrance::spec() const {
  return spec_text(
      {"he-torrance", {{"sigma0", sigma0_}, {"tau", tau_}, {"lambda", lambda_}, {"eta", eta_}, {"k", k_}, {"a", a_}}});
}

double HeTorrance::shadowing_over_cos(double mu, double sin_theta) const noexcept {
  if (!(sigma0_ > 0.0) || !(sin_theta > 0.0)) return mu > 0.0 ? 1.0 / mu : 0.0;  // S = 1
  // S/mu = [1 - erfc(a)/2] / ((1 + Lambda) mu) with (1 + Lambda) a = a + [e^{-a^2}/sqrt(pi) - a erfc a]/2
  // and a/mu = tau / (2 sigma0 sin theta): no division by mu (eqs. 24-25).
  const double b = tau_ / (2.0 * sigma0_ * sin_theta);
  const double a = b * mu;
  if (a > kShadowFree) return 1.0 / mu;
  const double e = std::erfc(a);
  const double den = a + 0.5 * (std::exp(-a * a) / std::sqrt(pi) - a * e);
  return (1.0 - 0.5 * e) * b / den;
}

double HeTorrance::shadowing(double mu) const noexcept {
  if (!(mu > 0.0)) return 0.0;
  mu = std::min(mu, 1.0);
  const double sin_theta = std::sqrt((1.0 - mu) * (1.0 + mu));
  if (!(sigma0_ > 0.0) || !(sin_theta > 0.0)) return 1.0;
  const double a = tau_ * mu / (2.0 * sigma0_ * sin_theta);
  if (a > kShadowFree) return 1.0;
  const double e = std::erfc(a);
  return (1.0 - 0.5 * e) * a / (a + 0.5 * (std::exp(-a * a) / std::sqrt(pi) - a * e));  // eqs. 24-25
}

double HeTorrance::K(double mu, double sin_theta) const noexcept {
  // K = tan theta erfc(tau cot theta / (2 sigma0)) (eqs. 82-83); +inf on the horizon.
  if (!(sin_theta > 0.0)) return 0.0;
  if (!(mu > 0.0)) return std::numeric_limits<double>::infinity();
  return sin_theta / mu * std::erfc(tau_ * mu / (2.0 * sigma0_ * sin_theta));
}

double HeTorrance::sigma_eff(double mu_i, double sin_i, double mu_r, double sin_r) const noexcept {
  if (!(sigma0_ > 0.0)) return 0.0;
  const double f0 = (K(mu_i, sin_i) + K(mu_r, sin_r)) / std::sqrt(8.0 * pi);  // eq. 81 with x = z0/sigma0
  if (std::isinf(f0)) return 0.0;                                             // grazing: the limit
  const double x = he_z0_over_sigma0(f0);
  return x > 1e150 ? sigma0_ / x : sigma0_ / std::sqrt(1.0 + x * x);  // eq. 80
}

double HeTorrance::effective_roughness(double cos_i, double cos_r) const noexcept {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  cos_r = std::clamp(cos_r, 0.0, 1.0);
  return sigma_eff(cos_i, std::sqrt((1.0 - cos_i) * (1.0 + cos_i)), cos_r, std::sqrt((1.0 - cos_r) * (1.0 + cos_r)));
}

double HeTorrance::specular_reflectance(double mu) const noexcept {
  mu = std::clamp(mu, 0.0, 1.0);
  const double F = fresnel_complex(mu, eta_, k_);
  if (!(sigma0_ > 0.0)) return F;  // smooth: a mirror
  const double S = shadowing(mu);  // S(theta_i) S(theta_r) with theta_r = theta_i
  if (!(S > 0.0)) return 0.0;
  const double sigma = effective_roughness(mu, mu);
  const double kappa = 2.0 * pi * sigma / lambda_;
  const double g = (kappa * 2.0 * mu) * (kappa * 2.0 * mu);  // eq. 79 with theta_r = theta_i
  return F * std::exp(-g) * S * S;                           // eqs. 73-74
}

double HeTorrance::directional_diffuse(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0 || !(sigma0_ > 0.0)) return 0.0;
  const double mu_i = std::min(i.z, 1.0), mu_j = std::min(j.z, 1.0);
  const double sin_i = std::hypot(i.x, i.y), sin_j = std::hypot(j.x, j.y);
  const Vec3 v = i + j;  // k_r - k_i with k_i = -i, k_r = j (eq. 84, unit vectors)
  const double vv = glm::dot(v, v);
  if (!(vv > 0.0)) return 0.0;
  const double sigma = sigma_eff(mu_i, sin_i, mu_j, sin_j);  // eqs. 80-83
  if (!(sigma > 0.0)) return 0.0;
  const double kappa = 2.0 * pi * sigma / lambda_;
  const double sum_mu = mu_i + mu_j;
  const double g = (kappa * sum_mu) * (kappa * sum_mu);  // eq. 79
  const double c = c_scale_ * (v.x * v.x + v.y * v.y);   // v_xy^2 tau^2/4, v = (2 pi/lambda)(i + j)
  // D / (mu_i + mu_j)^2 = prefactor kappa^2 T(g, c)  (eq. 78, g/(mu_i + mu_j)^2 = kappa^2);
  // G (mu_i + mu_j)^2 = (v.v)^2                        (eq. 76, brackets = |k_r x k_i|^4);
  // S / (mu_i mu_j) = (S_i/mu_i)(S_j/mu_j)             (eqs. 24-25).
  const double D_over = prefactor_ * kappa * kappa * he_series_over_g(g, c, kHeSeriesTolerance);
  const double G_times = vv * vv;
  const double S_over = shadowing_over_cos(mu_i, sin_i) * shadowing_over_cos(mu_j, sin_j);
  const double F = fresnel_complex(0.5 * std::sqrt(vv), eta_, k_);  // eq. 75 at the bisector: cos theta_d
  const double rho = F / pi * G_times * S_over * D_over;            // eq. 71
  return std::isfinite(rho) && rho > 0.0 ? rho : 0.0;
}

double HeTorrance::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return directional_diffuse(i, j) + a_ / pi;  // eqs. 71 + 72 (the delta of eq. 70 excluded)
}

std::optional<GlslF> HeTorrance::glsl_f() const {
  const std::string diffuse = decimal_literal(a_ / pi);
  if (!(sigma0_ > 0.0)) return GlslF{std::string(kGlslBelowHorizon) + "  return " + diffuse + ";\n", {}};
  const std::string tau = decimal_literal(tau_), sigma0 = decimal_literal(sigma0_);
  // As directional_diffuse() + a/pi: the effective roughness of eqs. 80-83 (0 when a direction
  // grazes: K is infinite there), g of eq. 79, the series of eq. 78 over g, G (mu_i + mu_j)^2 =
  // |i + j|^4, the shadowing over the cosines, Fresnel at the bisector.
  return GlslF{std::string(kGlslBelowHorizon) + "  float diffuse = " + diffuse +
                   ";\n"
                   "  float mu_i = min(i.z, 1.0), mu_j = min(j.z, 1.0);\n"
                   "  float sin_i = length(i.xy), sin_j = length(j.xy);\n"
                   "  vec3 v = i + j;\n"
                   "  float vv = dot(v, v);\n"
                   "  if (!(vv > 0.0)) return diffuse;\n"
                   "  if ((!(mu_i > 0.0) && sin_i > 0.0) || (!(mu_j > 0.0) && sin_j > 0.0)) return diffuse;\n"
                   "  float f0 = (gz_he_K(mu_i, sin_i, " +
                   tau + ", " + sigma0 + ") + gz_he_K(mu_j, sin_j, " + tau + ", " + sigma0 + ")) * " +
                   decimal_literal(1.0 / std::sqrt(8.0 * pi)) +
                   ";\n"
                   "  if (isinf(f0)) return diffuse;\n"
                   "  float x = gz_he_z0_over_sigma0(f0);\n"
                   "  float sigma = x > 1e18 ? " +
                   sigma0 + " / x : " + sigma0 +
                   " / sqrt(1.0 + x * x);\n"
                   "  if (!(sigma > 0.0)) return diffuse;\n"
                   "  float kappa = sigma * " +
                   decimal_literal(2.0 * pi / lambda_) +
                   ";\n"
                   "  float g = (kappa * (mu_i + mu_j)) * (kappa * (mu_i + mu_j));\n"
                   "  float c = " +
                   decimal_literal(c_scale_) +
                   " * dot(v.xy, v.xy);\n"
                   "  float D_over = " +
                   decimal_literal(prefactor_) +
                   " * kappa * kappa * gz_he_series_over_g(g, c);\n"
                   "  float S_over = gz_he_shadowing_over_cos(mu_i, sin_i, " +
                   tau + ", " + sigma0 + ") * gz_he_shadowing_over_cos(mu_j, sin_j, " + tau + ", " + sigma0 +
                   ");\n"
                   "  float F = gz_fresnel_complex(0.5 * sqrt(vv), " +
                   decimal_literal(eta_) + ", " + decimal_literal(k_) +
                   ");\n"
                   "  float rho = F * " +
                   decimal_literal(1.0 / pi) +
                   " * vv * vv * S_over * D_over;\n"
                   "  return (isinf(rho) || isnan(rho) || !(rho > 0.0) ? 0.0 : rho) + diffuse;\n",
               {"gz_he_terms", "gz_he_series_over_g", "gz_fresnel_complex"}};
}

std::optional<GlslF> HeTorrance::glsl_mirror_reflectance() const {
  // As specular_reflectance: F S^2 exp(-g), S = mu (S/mu), g of eq. 79 at theta_r = theta_i with the
  // effective roughness of eqs. 80-83 (glsl_f's steps with both directions at mu).
  const std::string fresnel = "gz_fresnel_complex(mu, " + decimal_literal(eta_) + ", " + decimal_literal(k_) + ")";
  if (!(sigma0_ > 0.0))
    return GlslF{"  float mu = clamp(c, 0.0, 1.0);\n  return " + fresnel + ";\n", {"gz_fresnel_complex"}};
  const std::string tau = decimal_literal(tau_), sigma0 = decimal_literal(sigma0_);
  return GlslF{
      "  float mu = clamp(c, 0.0, 1.0), sin_t = sqrt((1.0 - mu) * (1.0 + mu));\n"
      "  if (!(mu > 0.0)) return 0.0;\n"
      "  float S = mu * gz_he_shadowing_over_cos(mu, sin_t, " +
          tau + ", " + sigma0 +
          ");\n"
          "  if (!(S > 0.0)) return 0.0;\n"
          "  float f0 = 2.0 * gz_he_K(mu, sin_t, " +
          tau + ", " + sigma0 + ") * " + decimal_literal(1.0 / std::sqrt(8.0 * pi)) +
          ";\n"
          "  float x = isinf(f0) ? 0.0 : gz_he_z0_over_sigma0(f0);\n"
          "  float sigma = isinf(f0) ? 0.0 : x > 1e18 ? " +
          sigma0 + " / x : " + sigma0 +
          " / sqrt(1.0 + x * x);\n"
          "  float two_kappa_mu = 2.0 * mu * sigma * " +
          decimal_literal(2.0 * pi / lambda_) +
          ";\n"
          "  return " +
          fresnel + " * exp(-two_kappa_mu * two_kappa_mu) * S * S;\n",
      {"gz_he_terms", "gz_fresnel_complex"}};
}

MassHints HeTorrance::mass_hints(const Vec3& fixed, Varying) const {
  if (!(sigma0_ > 0.0)) return {};
  const Vec3 r = mirror(fixed);
  const double mu = std::clamp(fixed.z, 0.0, 1.0);
  const double sigma = effective_roughness(mu, mu);
  const double kappa = 2.0 * pi * sigma / lambda_;
  const double g = (kappa * 2.0 * mu) * (kappa * 2.0 * mu);
  // Term m of eq. 78 is exp(-v_xy^2 tau^2/(4m)): a Gaussian in (i + j)_xy of standard deviation
  // sqrt(2m)/(k tau) = sqrt(m) lambda/(sqrt(2) pi tau). Moving j by delta across the plane of
  // n and the peak moves (i + j)_xy by delta, along it by cos(theta_r) delta.
  const double w1 = lambda_ / (std::sqrt(2.0) * pi * tau_);
  HintBuilder hints;
  auto lobe = [&](double w) { hints.lobe(r, std::min(w / std::max(mu, 1e-6), pi / 2), std::min(w, pi / 2)); };
  lobe(w1);
  if (g > 4.0) lobe(w1 * std::sqrt(g));
  return hints.build();
}

// ---------------------------------------------------------------------------------------------
void register_he_torrance_models(std::vector<ModelInfo>& c) {
  c.push_back(
      {"he-torrance",
       "He-Torrance-Sillion-Greenberg physical optics (Kirchhoff, Gaussian surface), unpolarized: "
       "f = rho_dd + a/pi, rho_dd = F G S D/(pi (i.n)(j.n)), D the Beckmann series in g; the specular "
       "delta rho_s(theta_i) = |F|^2 exp(-g) S^2 into the mirror direction is not in f (nor in g, h, a of f): "
       "renders add it under skies and the Ganzfeld",
       "He, Torrance, Sillion & Greenberg 1991, SIGGRAPH '91, eqs. 69-84 and 24-25; Walker 1999, MSc thesis "
       "(U. Oregon), ch. III He-Torrance (eqs. III.13-III.18), app. D",
       {{"sigma0", ParamType::real, 0.0, 3.0, 0.15, "RMS surface height in micrometres (0 = smooth mirror)"},
        {"tau", ParamType::real, 0.1, 100.0, 1.5, "autocorrelation length in micrometres; 2 sigma0/tau <= 1"},
        {"lambda", ParamType::real, 0.2, 20.0, 0.55, "wavelength in micrometres"},
        {"eta", ParamType::real, 0.01, 10.0, 1.6, "real part of the complex index of refraction"},
        {"k", ParamType::real, 0.0, 20.0, 0.2, "imaginary part (extinction coefficient; thesis: n = 1.6 - .2i)"},
        {"a", ParamType::real, 0.0, 1.0, 0.0, "uniform-diffuse albedo, rho_ud = a/pi"}},
       {true, true, EnergyClass::not_plausible},
       {},
       [](const ParamValues& p) -> ModelPtr {
         const double sigma0 = p.at("sigma0"), tau = p.at("tau");
         // The Kirchhoff approximation needs gentle slopes: RMS slope m = 2 sigma0/tau <= 1.
         if (2.0 * sigma0 > tau)
           throw InputError("he-torrance: sigma0=" + format_number(sigma0) + " with tau=" + format_number(tau) +
                            " gives RMS slope 2 sigma0/tau = " + format_number(2.0 * sigma0 / tau) +
                            "; allowed: 2 sigma0/tau <= 1");
         return std::make_shared<HeTorrance>(sigma0, tau, p.at("lambda"), p.at("eta"), p.at("k"), p.at("a"));
       }});
}

}  // namespace ganzfeld
