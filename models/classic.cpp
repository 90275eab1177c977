// The classic models of the Oregon BRDF Library survey (Walker 1999): registered here.
// Formulas, sources and the differences from the thesis's summaries: models/classic_models.h and
// docs/models.md.
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "models/classic_models.h"
#include "models/registry.h"
#include "models/schlick.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

/// max(0, x)^n with 0 for x <= 0 (no 0^0 = 1 on the far side of a lobe).
double cosine_power(double x, double n) noexcept { return x > 0.0 ? std::pow(std::min(x, 1.0), n) : 0.0; }

/// Unit halfway vector; false when i + j vanishes (opposite directions on the horizon).
bool halfway(const Vec3& i, const Vec3& j, Vec3& h) noexcept {
  const Vec3 s = i + j;
  const double len = glm::length(s);
  if (!(len > 0.0)) return false;
  h = s / len;
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
double fresnel_complex(double cos_theta, double eta, double k) noexcept {
  using C = std::complex<double>;
  const double c = std::clamp(cos_theta, 0.0, 1.0);
  const C e(eta, k);
  const C sin2_t = (1.0 - c * c) / (e * e);  // Snell: sin theta_t = sin theta_i / (eta + i k)
  const C cos_t = std::sqrt(1.0 - sin2_t);
  const C den_s = c + e * cos_t, den_p = e * c + cos_t;
  // Both vanish only for eta + ik = 1 at grazing incidence, where the limit is total reflection.
  if (std::norm(den_s) == 0.0 || std::norm(den_p) == 0.0) return 1.0;
  const double r_s = std::norm((c - e * cos_t) / den_s);
  const double r_p = std::norm((e * c - cos_t) / den_p);
  return std::clamp(0.5 * (r_s + r_p), 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------------
Phong::Phong(double kd, double ks, double n, PhongLobe lobe) : kd_(kd), ks_(ks), n_(n), lobe_(lobe) {}

std::string Phong::spec() const {
  const char* name = lobe_ == PhongLobe::cosine_power ? "phong" : "schlick-phong";
  return spec_text({name, {{"kd", kd_}, {"ks", ks_}, {"n", n_}}});
}

double Phong::lobe(double cos_psi) const noexcept {
  return lobe_ == PhongLobe::cosine_power ? cosine_power(cos_psi, n_) : schlick::rational_phong(cos_psi, n_);
}

double Phong::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  // Phong's specular intensity carries no cos(theta_i): as a BRDF it is divided by mu_i.
  return kd_ / pi + ks_ * lobe(glm::dot(mirror(i), j)) / std::max(i.z, kGrazingCosFloor);
}

std::optional<GlslF> Phong::glsl_f() const {
  const std::string floor = decimal_literal(kGrazingCosFloor);
  if (lobe_ == PhongLobe::cosine_power)
    return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(kd_ / pi) + " + " +
                     decimal_literal(ks_) + " * gz_mirror_power(i, j, " + decimal_literal(n_) + ") / max(i.z, " +
                     floor + ");\n",
                 {"gz_mirror_power"}};
  // Schlick's rational t/(n - n t + t) = t/(n (1 - t) + t), t = k.j, 1 - t = |k - j|^2 / 2 for unit k, j
  // (as gz_mirror_power): no cancellation at the peak.
  const std::string n = decimal_literal(n_);
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 k = vec3(-i.x, -i.y, i.z), d = k - j;\n"
                   "  float t = dot(k, j);\n"
                   "  float lobe = t > 0.0 ? min(t, 1.0) / (" +
                   n +
                   " * (0.5 * dot(d, d)) + t) : 0.0;\n"
                   "  return " +
                   decimal_literal(kd_ / pi) + " + " + decimal_literal(ks_) + " * lobe / max(i.z, " + floor + ");\n",
               {}};
}

MassHints Phong::mass_hints(const Vec3& fixed, Varying varying) const {
  // cos^n psi ~ exp(-n psi^2 / 2): a Gaussian of standard deviation 1/sqrt(n) about the mirror.
  // Over incident directions k the specular part of (k·n) f is ks cos^n psi min(1, (k·n) /
  // kGrazingCosFloor): it falls linearly to 0 across the layer k·n < kGrazingCosFloor. With the
  // mirror lobe on the horizon (view at j·n <= 1e-6) the layer takes ks/2 kGrazingCosFloor times
  // the lobe's length along the horizon, ~1.4e-7 at n = 20, which no initial node sees
  // (tests/extremes_test.cpp, PhongGrazingLayerIsHonest). The layer holds at most ks/2 kGrazingCosFloor 2 pi
  // cos^n(e), e the mirror's elevation: it is declared when the lobe reaches the horizon, within
  // 4 widths of it (as ggx's layer).
  // Schlick's rational lobe 1/(1 + n (1 - t)/t) ~ 1/(1 + n psi^2/2) has the half width
  // sqrt(2/n) and tails t/n that reach the horizon for every mirror direction: its layer is
  // always declared.
  const bool rational = lobe_ == PhongLobe::schlick_rational;
  const double w = rational ? std::sqrt(2.0 / n_) : 1.0 / std::sqrt(n_);
  HintBuilder hints;
  hints.lobe(mirror(fixed), w);
  if (varying == Varying::incident && rational) hints.layer(kGrazingCosFloor);
  if (varying == Varying::incident)
    hints.layer_where_lobe_meets_horizon(std::asin(std::clamp(fixed.z, 0.0, 1.0)), w, kGrazingCosFloor);
  return hints.build();
}

PhongLewis::PhongLewis(double kd, double ks, double n) : kd_(kd), ks_(ks), n_(n), C_((n + 2.0) / (2.0 * pi)) {}

std::string PhongLewis::spec() const { return spec_text({"phong-lewis", {{"kd", kd_}, {"ks", ks_}, {"n", n_}}}); }

double PhongLewis::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return kd_ / pi + ks_ * C_ * cosine_power(glm::dot(mirror(i), j), n_);
}

std::optional<GlslF> PhongLewis::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(kd_ / pi) + " + " +
                   decimal_literal(ks_ * C_) + " * gz_mirror_power(i, j, " + decimal_literal(n_) + ");\n",
               {"gz_mirror_power"}};
}

MassHints PhongLewis::mass_hints(const Vec3& fixed, Varying) const {
  return HintBuilder().lobe(mirror(fixed), 1.0 / std::sqrt(n_)).build();
}

double blinn_phong_normalization(double n) {
  const double bracket =
      2.0 * (1.0 - std::exp2(-(n + 4.0) / 2.0)) / (n + 4.0) - (1.0 - std::exp2(-(n + 2.0) / 2.0)) / (n + 2.0);
  return 1.0 / (8.0 * pi * bracket);
}

BlinnPhong::BlinnPhong(double kd, double ks, double n) : kd_(kd), ks_(ks), n_(n), C_(blinn_phong_normalization(n)) {}

std::string BlinnPhong::spec() const { return spec_text({"blinn-phong", {{"kd", kd_}, {"ks", ks_}, {"n", n_}}}); }

double BlinnPhong::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  Vec3 h;
  if (!halfway(i, j, h)) return kd_ / pi;
  return kd_ / pi + ks_ * C_ * cosine_power(h.z, n_);
}

std::optional<GlslF> BlinnPhong::glsl_f() const {
  // (h.n)^n with 1 - h.n = |s_xy|^2 / (|s| (|s| + s_z)), s = i + j: exact to float rounding at the peak.
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 s = i + j;\n"
                   "  float len = length(s);\n"
                   "  if (!(len > 0.0)) return " +
                   decimal_literal(kd_ / pi) +
                   ";\n"
                   "  float y = dot(s.xy, s.xy) / (len * (len + s.z));\n"
                   "  return " +
                   decimal_literal(kd_ / pi) + " + " + decimal_literal(ks_ * C_) + " * gz_pow_pair(s.z / len, y, " +
                   decimal_literal(n_) + ");\n",
               {"gz_pow_pair"}};
}

MassHints BlinnPhong::mass_hints(const Vec3& fixed, Varying) const {
  // (h·n)^n ~ exp(-n delta^2 / 2) and delta ~ psi/2 near the mirror: width 2/sqrt(n) in psi.
  // Across the plane of n and the fixed direction v, tilting h by delta moves k = 2(v·h)h - v by
  // 2(v·n) delta only: the lobe is (v·n) times thinner across. With v on the horizon it is a cone
  // with its apex at mirror(v) = -v, where h = (k + v)/|k + v| turns vertical: (k·n)/sqrt(n) wide
  // at height k·n. The across width grades the grid towards the apex; without it the lobe went
  // unseen in the thin lune of g at i·n = -0.999 (ganzfeld extremes: 4.1e-5 off at n = 1000).
  // Floored (across = 0 would mean "as along"): the cone is self-similar about its apex, which
  // the grid's centre lines put on a panel corner, so below the finest line the bisection sees it
  // as at that scale. On the 88-case grid of blinn-phong (n = 1, 20, 1000, tolerance 1e-8) a
  // floor of 1e-9 cost 4.6-8.7x the evaluations, 1e-3 1.5-1.9x; both honest.
  const double along = 2.0 / std::sqrt(n_);
  return HintBuilder().lobe(mirror(fixed), along, along * std::max(fixed.z, 1e-3)).build();
}

// ---------------------------------------------------------------------------------------------
CookTorrance::CookTorrance(FacetDistribution d, double kd, double ks, double m, double eta, double k)
    : d_(d), kd_(kd), ks_(ks), m_(m), eta_(eta), k_(k) {
  if (d_ == FacetDistribution::gaussian) {
    // 1/c = 2 pi ∫_0^{pi/2} exp(-(delta/m)^2) cos delta sin delta d delta.
    const auto integrand = [m](double delta) {
      return std::exp(-(delta / m) * (delta / m)) * std::cos(delta) * std::sin(delta);
    };
    const double I = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(integrand, 0.0, pi / 2, 15, 1e-13);
    c_gauss_ = 1.0 / (2.0 * pi * I);
  }
}

std::string CookTorrance::spec() const {
  return spec_text({d_ == FacetDistribution::beckmann ? "cook-torrance" : "cook-torrance-gaussian",
                    {{"kd", kd_}, {"ks", ks_}, {"m", m_}, {"eta", eta_}, {"k", k_}}});
}

double CookTorrance::D(double c) const noexcept {
  if (!(c > 0.0)) return 0.0;
  c = std::min(c, 1.0);
  if (d_ == FacetDistribution::beckmann) {
    const double x = (1.0 - c * c) / (c * c * m_ * m_);  // tan^2 delta / m^2
    if (x > 700.0) return 0.0;                           // exp underflows before c^4 does
    const double c2 = c * c;
    return std::exp(-x) / (pi * m_ * m_ * c2 * c2);
  }
  const double delta = std::acos(c);
  return c_gauss_ * std::exp(-(delta / m_) * (delta / m_));
}

double CookTorrance::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double diffuse = kd_ / pi;
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return diffuse;
  // j·h = |i + j|/2 for unit i, j, as in the GLSL below: where i nears -j, dot(j, h) is
  // (1 + i·j)/|i + j|, and 1 + i·j (5e-17 at |i + j| = 1e-8) drowns in the 1e-16 by which a stored
  // direction misses unit length (tests/classic_test.cpp).
  const Vec3 h = sum / len;
  const double mu_i = i.z, mu_j = j.z, nh = h.z, jh = 0.5 * len;
  const double mu_max = std::max(mu_i, mu_j);
  if (!(mu_max > 0.0) || !(jh > 0.0)) return diffuse;
  // G/(mu_i mu_j) = min(1, 2 nh mu_j/jh, 2 nh mu_i/jh)/(mu_i mu_j)
  //               = min(1/(mu_i mu_j), (2 nh/jh)/max(mu_i, mu_j)): finite when one cosine vanishes.
  double G_over = 2.0 * nh / jh / mu_max;
  const double p = mu_i * mu_j;
  if (p > 0.0) G_over = std::min(G_over, 1.0 / p);
  const double s = fresnel_complex(jh, eta_, k_) * D(nh) * G_over / 4.0;
  return std::isfinite(s) ? diffuse + ks_ * s : diffuse;
}

std::optional<GlslF> CookTorrance::glsl_f() const {
  // D as CookTorrance::D, with tan^2 delta = |s_xy|^2 / s_z^2 and delta = atan2(|s_xy|, s_z) taken
  // from s = i + j (no 1 - cos^2 cancellation near the peak); j.h = |s|/2 for unit i, j.
  const std::string D = d_ == FacetDistribution::beckmann
                            ? "  float c2 = nh * nh;\n"
                              "  float D = exp(-dot(s.xy, s.xy) / (s.z * s.z * " +
                                  decimal_literal(m_ * m_) + ")) / (" + decimal_literal(pi * m_ * m_) + " * c2 * c2);\n"
                            : "  float delta = gz_atan2(length(s.xy), s.z);\n"
                              "  float D = " +
                                  decimal_literal(c_gauss_) + " * exp(-(delta * delta) * " +
                                  decimal_literal(1.0 / (m_ * m_)) + ");\n";
  const std::string diffuse = decimal_literal(kd_ / pi);
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 s = i + j;\n"
                   "  float len = length(s);\n"
                   "  if (!(len > 0.0)) return " +
                   diffuse +
                   ";\n"
                   "  float nh = s.z / len, jh = 0.5 * len;\n"
                   "  float mu_max = max(i.z, j.z);\n"
                   "  if (!(mu_max > 0.0) || !(jh > 0.0) || !(nh > 0.0)) return " +
                   diffuse +
                   ";\n"
                   "  float G_over = 2.0 * nh / jh / mu_max;\n"
                   "  float p = i.z * j.z;\n"
                   "  if (p > 0.0) G_over = min(G_over, 1.0 / p);\n" +
                   D + "  float spec = gz_fresnel_complex(jh, " + decimal_literal(eta_) + ", " + decimal_literal(k_) +
                   ") * D * G_over / 4.0;\n"
                   "  return isinf(spec) || isnan(spec) ? " +
                   diffuse + " : " + diffuse + " + " + decimal_literal(ks_) + " * spec;\n",
               {"gz_fresnel_complex", "gz_atan2"}};
}

MassHints CookTorrance::mass_hints(const Vec3& fixed, Varying) const {
  // exp(-tan^2 delta/m^2) ~ exp(-psi^2/(4 m^2)) near the mirror (psi ~ 2 delta): width sqrt(2) m.
  return HintBuilder().halfway_lobe(fixed, std::sqrt(2.0) * m_).build();
}

// ---------------------------------------------------------------------------------------------
Ward::Ward(double rho_d, double rho_s, double alpha_x, double alpha_y, bool anisotropic)
    : rho_d_(rho_d), rho_s_(rho_s), alpha_x_(alpha_x), alpha_y_(alpha_y), anisotropic_(anisotropic) {}

std::string Ward::spec() const {
  if (anisotropic_)
    return spec_text(
        {"ward-aniso", {{"rho_d", rho_d_}, {"rho_s", rho_s_}, {"alpha_x", alpha_x_}, {"alpha_y", alpha_y_}}});
  return spec_text({"ward", {{"rho_d", rho_d_}, {"rho_s", rho_s_}, {"alpha", alpha_x_}}});
}

double Ward::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double diffuse = rho_d_ / pi;
  const Vec3 h = i + j;  // unnormalized: tan^2 delta cos^2 phi_h = (h_x/h_z)^2
  if (!(h.z > 0.0)) return diffuse;
  const double ex = h.x / (alpha_x_ * h.z), ey = h.y / (alpha_y_ * h.z);
  const double e = ex * ex + ey * ey;
  if (!(e < 700.0)) return diffuse;
  const double root = std::sqrt(std::max(i.z * j.z, kGrazingCosFloor * kGrazingCosFloor));
  return diffuse + rho_s_ * std::exp(-e) / (4.0 * pi * alpha_x_ * alpha_y_ * root);
}

std::optional<GlslF> Ward::glsl_f() const {
  const std::string diffuse = decimal_literal(rho_d_ / pi);
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 h = i + j;\n"
                   "  if (!(h.z > 0.0)) return " +
                   diffuse +
                   ";\n"
                   "  float ex = h.x / (" +
                   decimal_literal(alpha_x_) + " * h.z), ey = h.y / (" + decimal_literal(alpha_y_) +
                   " * h.z);\n"
                   "  float e = ex * ex + ey * ey;\n"
                   "  if (!(e < 700.0)) return " +
                   diffuse +
                   ";\n"
                   "  float root = sqrt(max(i.z * j.z, " +
                   decimal_literal(kGrazingCosFloor * kGrazingCosFloor) +
                   "));\n"
                   "  return " +
                   diffuse + " + " + decimal_literal(rho_s_ / (4.0 * pi * alpha_x_ * alpha_y_)) +
                   " * exp(-e) / root;\n",
               {}};
}

std::optional<IncidentSample> Ward::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  if (!(j.z > 0.0)) return std::nullopt;
  const double total = rho_d_ + rho_s_;
  const double p_diffuse = total > 0.0 ? rho_d_ / total : 1.0;
  Vec3 i;
  if (u[0] < p_diffuse) {
    i = sample_cosine(u[1], u[2]);
  } else {
    const double phi = std::atan2(alpha_y_ * std::sin(2.0 * pi * u[2]), alpha_x_ * std::cos(2.0 * pi * u[2]));
    const double c = std::cos(phi), s = std::sin(phi);
    const double tan2 = -std::log(std::max(u[1], std::numeric_limits<double>::min())) /
                        (c * c / (alpha_x_ * alpha_x_) + s * s / (alpha_y_ * alpha_y_));
    const double cos_d = 1.0 / std::sqrt(1.0 + tan2), sin_d = std::sqrt(tan2) * cos_d;
    const Vec3 h{sin_d * c, sin_d * s, cos_d};
    i = 2.0 * glm::dot(j, h) * h - j;
  }
  return drawn_sample(*this, j, i);
}

double Ward::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const double total = rho_d_ + rho_s_;
  const double p_diffuse = total > 0.0 ? rho_d_ / total : 1.0;
  double lobe = 0.0;
  const Vec3 sum = i + j;
  if (p_diffuse < 1.0 && sum.z > 0.0) {
    const Vec3 h = glm::normalize(sum);
    const double ex = h.x / (alpha_x_ * h.z), ey = h.y / (alpha_y_ * h.z);
    const double e = ex * ex + ey * ey;
    if (e < 700.0) lobe = std::exp(-e) / (4.0 * pi * alpha_x_ * alpha_y_ * h.z * h.z * h.z * glm::dot(i, h));
  }
  return p_diffuse * i.z / pi + (1.0 - p_diffuse) * lobe;
}

MassHints Ward::mass_hints(const Vec3& fixed, Varying) const {
  return HintBuilder().lobe(mirror(fixed), std::sqrt(2.0) * std::min(alpha_x_, alpha_y_)).build();
}

// ---------------------------------------------------------------------------------------------
OrenNayar::OrenNayar(double sigma, double rho) : sigma_(sigma), rho_(rho) {}

std::string OrenNayar::spec() const { return spec_text({"oren-nayar", {{"sigma", sigma_}, {"rho", rho_}}}); }

MassHints OrenNayar::mass_hints(const Vec3& fixed, Varying) const {
  // tan beta and tan((alpha + beta)/2) are floored at kGrazingCosFloor where both directions
  // graze: with `fixed` within a few floors of the horizon, (k·n) f ramps to its limit across
  // k·n < kGrazingCosFloor (a 12x dishonest g at i·n = j·n = 0 without it:
  // tests/extremes_test.cpp): kGrazingLayer.
  return HintBuilder().layer(fixed.z < 10.0 * kGrazingCosFloor ? kGrazingLayer : 0.0).build();
}

double OrenNayar::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double mu_i = std::min(i.z, 1.0), mu_j = std::min(j.z, 1.0);
  const double theta_i = std::acos(mu_i), theta_r = std::acos(mu_j);
  const double alpha = std::max(theta_i, theta_r), beta = std::min(theta_i, theta_r);
  // cos(phi_r - phi_i) from the projections on the surface; 0 when an azimuth is undefined
  // (then beta = 0 and every azimuthal term vanishes anyway).
  const double pxy = std::hypot(i.x, i.y) * std::hypot(j.x, j.y);
  const double cos_dphi = pxy > 0.0 ? std::clamp((i.x * j.x + i.y * j.y) / pxy, -1.0, 1.0) : 0.0;
  const double s2 = sigma_ * sigma_;
  const double C1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
  const double two_beta_pi = 2.0 * beta / pi;
  double C2 = 0.45 * s2 / (s2 + 0.09) * std::sin(alpha);
  if (cos_dphi < 0.0) C2 = 0.45 * s2 / (s2 + 0.09) * (std::sin(alpha) - two_beta_pi * two_beta_pi * two_beta_pi);
  const double C3 = 0.125 * s2 / (s2 + 0.09) * std::pow(4.0 * alpha * beta / (pi * pi), 2);
  // tan beta and tan((alpha+beta)/2) diverge only when both directions graze: kGrazingCosFloor.
  const double tan_beta = std::sin(beta) / std::max(std::cos(beta), kGrazingCosFloor);
  const double half = 0.5 * (alpha + beta);
  const double tan_half = std::sin(half) / std::max(std::cos(half), kGrazingCosFloor);
  const double L1 = rho_ / pi * (C1 + cos_dphi * C2 * tan_beta + (1.0 - std::abs(cos_dphi)) * C3 * tan_half);
  const double L2 = 0.17 * rho_ * rho_ / pi * s2 / (s2 + 0.13) * (1.0 - cos_dphi * two_beta_pi * two_beta_pi);
  return L1 + L2;
}

std::optional<GlslF> OrenNayar::glsl_f() const {
  // In the elevations e = pi/2 - theta, from the direction's own components (exact at the horizon,
  // where the terms below nearly cancel): of the lower direction (alpha) cos e_a = s_a, sin e_a =
  // mu_a; of the higher (beta) s_b, mu_b. sin alpha - (2 beta/pi)^3 = u (3 - 3u + u^2) - (1 - s_a),
  // u = 2 e_b/pi, 1 - s_a = mu_a^2/(1 + s_a); tan beta = s_b/mu_b; tan((alpha + beta)/2) = cos h /
  // sin h with h the mean elevation: cos h = sqrt((1 + cos E)/2), sin h = sin E/(2 cos h), E = e_a + e_b;
  // 1 - |cos dphi| = sin^2 dphi/(1 + |cos dphi|).
  const double s2 = sigma_ * sigma_;
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float si = length(i.xy), sj = length(j.xy);\n"
                   "  float e_i = gz_atan2(i.z, si), e_j = gz_atan2(j.z, sj);\n"
                   "  bool i_lower = e_i <= e_j;\n"
                   "  float e_a = i_lower ? e_i : e_j, e_b = i_lower ? e_j : e_i;\n"
                   "  float s_a = i_lower ? si : sj, mu_a = i_lower ? i.z : j.z;\n"
                   "  float s_b = i_lower ? sj : si, mu_b = i_lower ? j.z : i.z;\n"
                   "  float alpha = 1.5707963268 - e_a, beta = 1.5707963268 - e_b;\n"
                   "  float pxy = si * sj;\n"
                   "  float cos_dphi = pxy > 0.0 ? clamp(dot(i.xy, j.xy) / pxy, -1.0, 1.0) : 0.0;\n"
                   "  float sin_dphi = pxy > 0.0 ? (i.x * j.y - i.y * j.x) / pxy : 0.0;\n"
                   "  float one_minus_abs_cos = pxy > 0.0 ? sin_dphi * sin_dphi / (1.0 + abs(cos_dphi)) : 1.0;\n"
                   "  float two_beta_pi = 2.0 * beta / 3.1415926536, u = 2.0 * e_b / 3.1415926536;\n"
                   "  float C2 = " +
                   decimal_literal(0.45 * s2 / (s2 + 0.09)) +
                   " * (cos_dphi < 0.0 ? u * (3.0 - 3.0 * u + u * u) - mu_a * mu_a / (1.0 + s_a) : s_a);\n"
                   "  float q = 4.0 * alpha * beta / 9.8696044011;\n"
                   "  float C3 = " +
                   decimal_literal(0.125 * s2 / (s2 + 0.09)) +
                   " * q * q;\n"
                   "  float tan_beta = s_b / max(mu_b, " +
                   decimal_literal(kGrazingCosFloor) +
                   ");\n"
                   "  float cos_E = s_a * s_b - mu_a * mu_b, sin_E = mu_a * s_b + s_a * mu_b;\n"
                   "  float cos_h = sqrt(max(0.5 * (1.0 + cos_E), 0.0));\n"
                   "  float sin_h = cos_h > 0.0 ? 0.5 * sin_E / cos_h : 1.0;\n"
                   "  float tan_half = cos_h / max(sin_h, " +
                   decimal_literal(kGrazingCosFloor) +
                   ");\n"
                   "  float L1 = " +
                   decimal_literal(rho_ / pi) + " * (" + decimal_literal(1.0 - 0.5 * s2 / (s2 + 0.33)) +
                   " + cos_dphi * C2 * tan_beta + one_minus_abs_cos * C3 * tan_half);\n"
                   "  float L2 = " +
                   decimal_literal(0.17 * rho_ * rho_ / pi * s2 / (s2 + 0.13)) +
                   " * (1.0 - cos_dphi * two_beta_pi * two_beta_pi);\n"
                   "  return L1 + L2;\n",
               {"gz_atan2"}};
}

// ---------------------------------------------------------------------------------------------
Lafortune::Lafortune(double kd, double C_x, double C_y, double C_z, double n) : kd_(kd), lobes_{{C_x, C_y, C_z, n}} {}

Lafortune::Lafortune(double kd, std::vector<Lobe> lobes, std::string spec)
    : kd_(kd), lobes_(std::move(lobes)), preset_(std::move(spec)) {}

std::string Lafortune::spec() const {
  if (!preset_.empty()) return preset_;
  const Lobe& l = lobes_.front();
  return spec_text({"lafortune", {{"kd", kd_}, {"Cx", l.C_x}, {"Cy", l.C_y}, {"Cz", l.C_z}, {"n", l.n}}});
}

Traits Lafortune::traits() const {
  bool isotropic = true;
  for (const Lobe& l : lobes_) isotropic = isotropic && l.C_x == l.C_y;
  return {isotropic, true, EnergyClass::not_plausible};
}

double Lafortune::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  double sum = kd_ / pi;
  for (const Lobe& l : lobes_) {
    const double x = l.C_x * i.x * j.x + l.C_y * i.y * j.y + l.C_z * i.z * j.z;
    if (x > 0.0) sum += std::pow(x, l.n);
  }
  return sum;
}

std::optional<GlslF> Lafortune::glsl_f() const {
  // As f, for the directions î, ĵ of i, j (the CPU's are unit): x = (C∘ĵ)·î = |C∘ĵ| cos, with
  // cos = î·û, û = C∘ĵ/|C∘ĵ|, so x^n = (1 + s)^(n/2) cos^n, s = Σ (C_k² − 1) ĵ_k² / |ĵ|² (0 for a mirror,
  // every |C_k| = 1), and 1 − cos = |î − û|²/2 formed without cancellation (gz_pow_pair): x^n rounded
  // from x itself errs by n ulps (n up to 10^4).
  std::string body = std::string(kGlslBelowHorizon) + "  float sum = " + decimal_literal(kd_ / pi) +
                     ";\n  vec3 in_ = normalize(i), jn = normalize(j), u, d;\n";
  double power = 0.0;
  for (const Lobe& l : lobes_) {
    const std::string c =
        "vec3(" + decimal_literal(l.C_x) + ", " + decimal_literal(l.C_y) + ", " + decimal_literal(l.C_z) + ")";
    const std::string c2m1 = "vec3(" + decimal_literal(l.C_x * l.C_x - 1.0) + ", " +
                             decimal_literal(l.C_y * l.C_y - 1.0) + ", " + decimal_literal(l.C_z * l.C_z - 1.0) + ")";
    body += "  u = " + c + " * jn;\n  if (dot(in_, u) > 0.0) {\n    u = normalize(u);\n    d = in_ - u;\n" +
            "    sum += exp(" + decimal_literal(0.5 * l.n) + " * gz_log1p(dot(" + c2m1 +
            " * jn, jn) / dot(jn, jn))) * gz_pow_pair(dot(in_, u), 0.5 * dot(d, d), " + decimal_literal(l.n) +
            ");\n  }\n";
    power = std::max(power, l.n);
  }
  return GlslF{body + "  return sum;\n", {"gz_log1p", "gz_pow_pair"}, power};
}

MassHints Lafortune::mass_hints(const Vec3& fixed, Varying) const {
  // Each lobe peaks along (Cx x, Cy y, Cz z) of the fixed direction; width ~ 1/sqrt(n).
  HintBuilder hints;
  for (const Lobe& l : lobes_) {
    const Vec3 axis{l.C_x * fixed.x, l.C_y * fixed.y, l.C_z * fixed.z};
    const double len = glm::length(axis);
    if (len > 0.0) hints.lobe(axis / len, 1.0 / std::sqrt(l.n));
  }
  return hints.build();
}

ModelPtr lafortune_paint(int channel) {
  // Lafortune et al. 1997, blue paint: diffuse, then three lobes (Cxy, Cz, n) per channel R, G, B.
  static constexpr double kd[3] = {0.3094, 0.39667, 0.70837};
  static constexpr double lobes[3][3][3] = {
      {{0.870567, 0.803624, 21.820103}, {-0.451218, 0.023123, 2.774499}, {-1.031545, 0.706734, 66.899060}},
      {{0.857255, 0.774290, 18.597755}, {-0.406681, 0.017625, 2.581499}, {-1.029426, 0.696530, 63.767912}},
      {{0.670982, 0.586674, 7.472717}, {-0.477976, 0.227295, 3.677653}, {-1.026588, 0.687715, 57.489181}}};
  std::vector<Lafortune::Lobe> l;
  for (const auto& c : lobes[channel]) l.push_back({c[0], c[0], c[1], c[2]});
  return std::make_shared<Lafortune>(kd[channel], std::move(l),
                                     spec_text({"lafortune-paint", {{"channel", static_cast<double>(channel)}}}));
}

// ---------------------------------------------------------------------------------------------
Hapke::Hapke(double rho, double g, HapkePhase phase) : rho_(rho), g_(g), phase_(phase) {}

std::string Hapke::spec() const {
  return spec_text({"hapke", {{"rho", rho_}, {"g", g_}, {"phase", static_cast<double>(phase_)}}});
}

double Hapke::B(double tan_alpha, double cos_alpha, double g) noexcept {
  if (!(cos_alpha > 0.0)) return 1.0;                      // alpha >= pi/2 (the limit from below is 1 too)
  if (!(tan_alpha > 0.0)) return 2.0;                      // alpha = 0: the full opposition surge
  const double one_minus_e = -std::expm1(-g / tan_alpha);  // accurate as tan alpha -> inf
  return 2.0 - tan_alpha / (2.0 * g) * one_minus_e * (2.0 + one_minus_e);
}

double Hapke::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double cos_a = std::clamp(glm::dot(i, j), -1.0, 1.0);
  const double sin_a = glm::length(glm::cross(i, j));  // accurate near alpha = 0
  const double a = std::atan2(sin_a, cos_a);
  const double tan_a = cos_a > 0.0 ? sin_a / cos_a : 0.0;  // unused by B when cos_a <= 0
  double S = 1.0;
  if (phase_ == HapkePhase::forward) S = 4.0 / 9.0 * (1.0 - 0.5 * cos_a) * (1.0 - 0.5 * cos_a);
  if (phase_ == HapkePhase::back) S = std::max(0.0, (sin_a + (pi - a) * cos_a) / pi);
  return rho_ * S * B(tan_a, cos_a, g_) / (pi * std::max(i.z + j.z, kGrazingCosFloor));
}

std::optional<GlslF> Hapke::glsl_f() const {
  std::string S = "1.0";
  if (phase_ == HapkePhase::forward) S = "0.444444444 * (1.0 - 0.5 * cos_a) * (1.0 - 0.5 * cos_a)";
  // sin a + (pi - a) cos a = sin d - d cos d, d = pi - a: gz_lambert_sphere_bracket.
  if (phase_ == HapkePhase::back) S = "gz_lambert_sphere_bracket(i, j) / 3.1415926536";
  // B(alpha, g) as Hapke::B; 1 - cos alpha from |i - j|^2/2, sin alpha from |i x j|.
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 d = i - j;\n"
                   "  float cos_a = clamp(1.0 - 0.5 * dot(d, d), -1.0, 1.0);\n"
                   "  float sin_a = length(cross(i, j));\n"
                   "  float B = 1.0;\n"
                   "  if (cos_a > 0.0) {\n"
                   "    float tan_a = sin_a / cos_a;\n"
                   "    if (!(tan_a > 0.0)) {\n"
                   "      B = 2.0;\n"
                   "    } else {\n"
                   "      float one_minus_e = -gz_expm1(-" +
                   decimal_literal(g_) +
                   " / tan_a);\n"
                   "      B = 2.0 - tan_a * " +
                   decimal_literal(0.5 / g_) +
                   " * one_minus_e * (2.0 + one_minus_e);\n"
                   "    }\n"
                   "  }\n"
                   "  return " +
                   decimal_literal(rho_ / pi) + " * " + S + " * B / max(i.z + j.z, " +
                   decimal_literal(kGrazingCosFloor) + ");\n",
               {"gz_lambert_sphere_bracket", "gz_expm1"}};
}

MassHints Hapke::mass_hints(const Vec3& fixed, Varying) const {
  // The opposition surge on `fixed` (B falls from 2 over tan alpha ~ g), and the
  // Lommel–Seeliger factor (k·n)/((k + fixed)·n) switching over k·n ~ fixed·n; a grazing `fixed`
  // leaves the ramp of its floor, k·n < kGrazingCosFloor: kGrazingLayer.
  return HintBuilder().lobe(fixed, std::min(g_, 1.0)).layer(std::max(fixed.z, kGrazingLayer)).build();
}

// ---------------------------------------------------------------------------------------------
void require_sum_at_most_one(const std::string& model, const char* a, double va, const char* b, double vb) {
  if (va + vb > 1.0)
    throw InputError(model + ": " + a + "=" + format_number(va) + " + " + b + "=" + format_number(vb) + " = " +
                     format_number(va + vb) + " exceeds 1; allowed: " + a + " + " + b + " <= 1");
}

ParamInfo kd_param(double def) {
  return {"kd", ParamType::real, 0.0, 1.0, def, "Lambertian (diffuse) reflectance; kd + ks <= 1"};
}
ParamInfo ks_param(double def) {
  return {"ks", ParamType::real, 0.0, 1.0, def, "specular reflectance (weight of the lobe); kd + ks <= 1"};
}
ParamInfo n_param(double def, const char* meaning) { return {"n", ParamType::real, 1.0, 10000.0, def, meaning}; }

namespace {

const char* kWalker = "Walker 1999, MSc thesis (U. Oregon), ch. III";

/// The registry entry of a Phong-type model M(kd, ks, n, extra...): kd and ks with kd + ks <= 1,
/// the exponent n (n_param, `n_meaning`).
template <class M, class... Extra>
ModelInfo phong_type_info(const char* name, std::string summary, std::string source, const char* n_meaning,
                          Traits traits, Extra... extra) {
  return {name,
          std::move(summary),
          std::move(source),
          {kd_param(0.5), ks_param(0.5), n_param(20.0, n_meaning)},
          traits,
          {},
          [name, extra...](const ParamValues& p) -> ModelPtr {
            require_sum_at_most_one(name, "kd", p.at("kd"), "ks", p.at("ks"));
            return std::make_shared<M>(p.at("kd"), p.at("ks"), p.at("n"), extra...);
          }};
}

ModelInfo cook_torrance_info(FacetDistribution d) {
  const bool beckmann = d == FacetDistribution::beckmann;
  return {beckmann ? "cook-torrance" : "cook-torrance-gaussian",
          std::string("microfacet specular + Lambert, f = kd/pi + ks F D G/(pi (i.n)(j.n)); D = ") +
              (beckmann ? "Beckmann exp(-tan^2 d/m^2)/(4 m^2 cos^4 d)" : "Gaussian c exp(-(d/m)^2)") +
              ", V-groove G, exact Fresnel for eta + ik",
          std::string("Cook & Torrance 1981, SIGGRAPH '81; ") + kWalker + ", Cook-Torrance",
          {kd_param(0.3),
           ks_param(0.7),
           {"m", ParamType::real, 0.01, 1.0, 0.15, "RMS slope of the microfacets (roughness)"},
           {"eta", ParamType::real, 0.01, 10.0, 1.6, "real part of the complex index of refraction"},
           {"k", ParamType::real, 0.0, 20.0, 0.2, "imaginary part (extinction coefficient)"}},
          {true, true, EnergyClass::plausible},
          {},
          [d](const ParamValues& p) -> ModelPtr {
            const std::string name = d == FacetDistribution::beckmann ? "cook-torrance" : "cook-torrance-gaussian";
            require_sum_at_most_one(name, "kd", p.at("kd"), "ks", p.at("ks"));
            return std::make_shared<CookTorrance>(d, p.at("kd"), p.at("ks"), p.at("m"), p.at("eta"), p.at("k"));
          }};
}

}  // namespace

void register_classic_models(std::vector<ModelInfo>& c) {
  c.push_back(phong_type_info<Phong>("phong",
                                     "original Phong as a BRDF, f = kd/pi + ks cos^n(psi)/(i.n) (not reciprocal)",
                                     std::string("Phong 1975, CACM 18(6); ") + kWalker + ", Phong (eq. III.6)",
                                     "specular exponent", {true, false, EnergyClass::not_plausible}));
  c.push_back(phong_type_info<Phong>(
      "schlick-phong",
      "original Phong with Schlick's rational lobe, f = kd/pi + ks t/(n - n t + t)/(i.n), t = max(0, cos psi)",
      std::string("Schlick 1994, Computer Graphics Forum 13(3) (rational approximation); ") + kWalker +
          ", Phong (Figs. 17, 19)",
      "exponent the rational lobe approximates", {true, false, EnergyClass::not_plausible},
      PhongLobe::schlick_rational));
  c.push_back(
      phong_type_info<PhongLewis>("phong-lewis", "Lewis's normalized Phong, f = kd/pi + ks (n+2)/(2 pi) cos^n(psi)",
                                  std::string("Lewis 1994, Computer Graphics Forum 13(2); ") + kWalker + ", Phong",
                                  "specular exponent", {true, true, EnergyClass::plausible}));
  c.push_back(phong_type_info<BlinnPhong>(
      "blinn-phong", "halfway-vector Phong, f = kd/pi + ks C(n) (h.n)^n, C(n): unit albedo at normal incidence",
      std::string("Blinn 1977, SIGGRAPH '77; ") + kWalker + ", Phong (halfway variant)", "exponent of h.n",
      {true, true, EnergyClass::plausible}));
  c.push_back(cook_torrance_info(FacetDistribution::beckmann));
  c.push_back(cook_torrance_info(FacetDistribution::gaussian));
  c.push_back({"ward",
               "isotropic Ward, f = rho_d/pi + rho_s exp(-tan^2 d/alpha^2)/(4 pi alpha^2 sqrt((i.n)(j.n)))",
               std::string("Ward 1992, SIGGRAPH '92, eq. 4a; ") + kWalker + ", Ward (eq. III.22)",
               {{"rho_d", ParamType::real, 0.0, 1.0, 0.5, "diffuse reflectance; rho_d + rho_s <= 1"},
                {"rho_s", ParamType::real, 0.0, 1.0, 0.1, "specular reflectance; rho_d + rho_s <= 1"},
                {"alpha", ParamType::real, 0.01, 1.0, 0.1, "RMS slope of the surface (lobe width)"}},
               {true, true, EnergyClass::not_plausible},
               {},
               [](const ParamValues& p) -> ModelPtr {
                 require_sum_at_most_one("ward", "rho_d", p.at("rho_d"), "rho_s", p.at("rho_s"));
                 return std::make_shared<Ward>(p.at("rho_d"), p.at("rho_s"), p.at("alpha"), p.at("alpha"), false);
               }});
  c.push_back({"ward-aniso",
               "anisotropic Ward (tangent = local x axis), elliptical Gaussian in the halfway slope",
               std::string("Ward 1992, SIGGRAPH '92, eq. 5a; ") + kWalker + ", Ward (eq. III.23)",
               {{"rho_d", ParamType::real, 0.0, 1.0, 0.10, "diffuse reflectance; rho_d + rho_s <= 1"},
                {"rho_s", ParamType::real, 0.0, 1.0, 0.33, "specular reflectance; rho_d + rho_s <= 1"},
                {"alpha_x", ParamType::real, 0.01, 1.0, 0.05, "RMS slope along the tangent (x)"},
                {"alpha_y", ParamType::real, 0.01, 1.0, 0.16, "RMS slope along the bitangent (y)"}},
               {false, true, EnergyClass::not_plausible},
               {},
               [](const ParamValues& p) -> ModelPtr {
                 require_sum_at_most_one("ward-aniso", "rho_d", p.at("rho_d"), "rho_s", p.at("rho_s"));
                 return std::make_shared<Ward>(p.at("rho_d"), p.at("rho_s"), p.at("alpha_x"), p.at("alpha_y"), true);
               }});
  c.push_back(
      {"oren-nayar",
       "rough Lambertian facets (V-cavities), full model with interreflections (L1 + L2)",
       std::string("Oren & Nayar 1994, SIGGRAPH '94, eqs. 8 and 11; ") + kWalker +
           ", Oren-Nayar (eqs. III.25-26, app. D)",
       {{"sigma", ParamType::real, 0.0, 0.6, 0.3,
         "RMS facet slope angle in radians (<= 0.6: beyond ~0.68 the model goes negative)"},
        {"rho", ParamType::real, 0.0, 1.0, 0.8, "albedo of the Lambertian facets"}},
       {true, true, EnergyClass::not_plausible},
       {},
       [](const ParamValues& p) -> ModelPtr { return std::make_shared<OrenNayar>(p.at("sigma"), p.at("rho")); }});
  c.push_back({"lafortune",
               "one generalized cosine lobe + Lambert, f = kd/pi + max(0, Cx ix jx + Cy iy jy + Cz iz jz)^n",
               std::string("Lafortune et al. 1997, SIGGRAPH '97, eq. 4; ") + kWalker + ", Lafortune (eq. III.32)",
               {kd_param(0.5),
                {"Cx", ParamType::real, -10.0, 10.0, -1.0, "lobe coefficient along the tangent (x)"},
                {"Cy", ParamType::real, -10.0, 10.0, -1.0, "lobe coefficient along the bitangent (y)"},
                {"Cz", ParamType::real, -10.0, 10.0, 1.0, "lobe coefficient along the normal (z)"},
                {"n", ParamType::real, 1.0, 10000.0, 20.0, "lobe exponent; n log10(max|C|) <= 300"}},
               {false, true, EnergyClass::not_plausible},
               {},
               [](const ParamValues& p) -> ModelPtr {
                 const double c_max = std::max({std::abs(p.at("Cx")), std::abs(p.at("Cy")), std::abs(p.at("Cz"))});
                 if (c_max > 1.0 && p.at("n") * std::log10(c_max) > 300.0)
                   throw InputError("lafortune: n=" + format_number(p.at("n")) + " with max|C|=" +
                                    format_number(c_max) + " overflows; allowed: n log10(max|C|) <= 300");
                 return std::make_shared<Lafortune>(p.at("kd"), p.at("Cx"), p.at("Cy"), p.at("Cz"), p.at("n"));
               }});
  c.push_back({"lafortune-paint",
               "Lafortune et al.'s three-lobe fit to measured blue paint (one RGB channel), f = kd/pi + sum of 3 lobes",
               std::string("Lafortune, Foo, Torrance, Greenberg 1997, SIGGRAPH '97 (blue paint fit); ") + kWalker +
                   ", Lafortune (fig. 35)",
               {{"channel", ParamType::integer, 0.0, 2.0, 2.0, "0 red, 1 green, 2 blue"}},
               {true, true, EnergyClass::not_plausible},
               {},
               [](const ParamValues& p) -> ModelPtr { return lafortune_paint(static_cast<int>(p.at("channel"))); }});
  c.push_back({"hapke",
               "Hapke/Lommel-Seeliger lunar law, f = rho S(a) B(a, g)/(pi (i.n + j.n)), a = phase angle",
               std::string("Hapke 1963, J. Geophys. Res. 68; ") + kWalker + ", Hapke/Lommel-Seeliger (eqs. III.27-29)",
               {{"rho", ParamType::real, 0.0, 1.0, 0.5, "single-scattering reflectance (scale)"},
                {"g", ParamType::real, 0.01, 10.0, 0.6, "compaction g = 2y/tau (opposition-surge width)"},
                {"phase", ParamType::integer, 0.0, 2.0, 0.0, "phase law S: 0 isotropic, 1 forward, 2 back"}},
               {true, true, EnergyClass::not_plausible},
               {},
               [](const ParamValues& p) -> ModelPtr {
                 const auto phase = static_cast<HapkePhase>(static_cast<int>(p.at("phase")));
                 return std::make_shared<Hapke>(p.at("rho"), p.at("g"), phase);
               }});
}

}  // namespace ganzfeld
