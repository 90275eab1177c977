// He, Torrance, Sillion & Greenberg 1991 ("A comprehensive physical model for light
// reflection", SIGGRAPH '91, Computer Graphics 25(4) 175-186; "HTSG"), unpolarized form; Walker
// 1999 (MSc thesis, U. Oregon) ch. III "He-Torrance", eqs. III.13-III.18 and appendix D.
// Equation numbers below are the paper's (eqs. 69-84 of its section 5, "unpolarized"; eqs. 23-25
// for the shadowing function), as also used by the Cornell reference code of S. Westin.
//
//   rho = rho_sp + rho_dd + rho_ud                                             (eq. 69)
//   rho_sp = rho_s Delta / (cos theta_i d omega_i),  rho_s = |F(theta_i)|^2 e^{-g} S  (eqs. 70, 73-74)
//   rho_dd = |F(theta_d)|^2 G S D / (pi cos theta_i cos theta_r)               (eq. 71)
//   rho_ud = a / pi                                                            (eq. 72)
//   G = (v.v / v_z)^2 [(s_r.k_i)^2 + (p_r.k_i)^2][(s_i.k_r)^2 + (p_i.k_r)^2] / |k_r x k_i|^4 (eq. 76)
//     = (v.v / v_z)^2 exactly: {s, p, k} is an orthonormal triad, so each bracket equals
//       1 - (k_i.k_r)^2 = |k_r x k_i|^2 (tested).
//   D = (pi^2 tau^2 / (4 lambda^2)) sum_{m>=1} g^m e^{-g} / (m! m) exp(-v_xy^2 tau^2 / (4m))  (eq. 78)
//   g = [(2 pi sigma / lambda)(cos theta_i + cos theta_r)]^2                   (eq. 79)
//   sigma = sigma0 [1 + (z0/sigma0)^2]^{-1/2},                                 (eq. 80)
//   sqrt(pi/2) z0 = (sigma0/4)(K_i + K_r) exp(-z0^2/(2 sigma0^2)),             (eq. 81)
//   K = tan theta erfc(tau cot theta / (2 sigma0))                             (eqs. 82-83)
//   S = S(theta_i) S(theta_r), S(theta) = [1 - erfc(a)/2] / [Lambda(a) + 1],   (eq. 24)
//   Lambda(a) = [exp(-a^2)/(sqrt(pi) a) - erfc(a)] / 2,  a = tau cot theta / (2 sigma0)  (eq. 25)
// with, in ganzfeld's frame (n = +z, i towards the light, j towards the eye), k_i = -i, k_r = j,
// the unit-vector difference v^ = k_r - k_i = i + j for G and the wave-vector difference
// v = (2 pi/lambda)(i + j) in D's exponent (eq. 84), and theta_d the local angle of incidence on
// the facet bisecting k_i and k_r: cos theta_d = |i + j|/2.
//
// Deliberate choices (docs: models_section.md):
//  - Lambda includes Smith's exp(-a^2) (Smith 1967; Pacanowski & Holzschuch's errata; Westin's
//    code): the paper and the thesis print it without.
//  - D's exponent uses the wave vector (dimensionless v_xy^2 tau^2); taking the unit vector
//    there (as a literal reading of the printed eq. 78 suggests) makes the result depend on the
//    unit of tau. With these choices rho_dd tends, as g -> infinity, to the Beckmann microfacet
//    BRDF F S D_Beckmann(m = 2 sigma/tau) / (4 cos theta_i cos theta_r) (tested).
//  - The specular term is a Dirac delta about the mirror direction: f() excludes it;
//    specular_reflectance(cos theta_i) gives its weight rho_s (the fraction of the incident flux
//    reflected coherently into the mirror direction). The hemispherical reflectance of the whole
//    model is albedo(f) + rho_s.
//  - Horizon: 1/(cos theta_i cos theta_r) and G's 1/v_z^2 are cancelled analytically, not
//    floored: S(theta)/cos theta has the finite limit sqrt(pi) tau/(2 sigma0) at theta = 90 deg,
//    and g/(cos theta_i + cos theta_r)^2 = (2 pi sigma/lambda)^2 is divided out of the series
//    (he_series_over_g). f is finite everywhere and tends to a/pi on the horizon (sigma -> 0
//    there, logarithmically slowly).
#pragma once

#include <string>
#include <vector>

#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

/// Relative tolerance to which f sums the series of eq. 78: the neglected tails are bounded
/// rigorously (see he_series_over_g), so the sum is within this factor of its exact value
/// (plus a few ulps of rounding per hundred terms).
inline constexpr double kHeSeriesTolerance = 1e-12;

/// Series of eq. 78 without its prefactor, divided by g:
///   T(g, c) = sum_{m>=1} e^{-g} g^{m-1}/m! * e^{-c/m}/m,   c = v_xy^2 tau^2 / 4 >= 0,
/// finite as g -> 0 (T(0, c) = e^{-c}). Summed outwards from the mode of the Poisson weights
/// (m ~ g) in both directions; each direction stops when a rigorous bound on its remaining
/// tail (geometric bound on the Poisson weights times the maximum of e^{-c/m}/m beyond) falls
/// below rel_tol/2 of the partial sum, or below the smallest normal double. Poisson weights
/// come from Boost's gamma_p_derivative (log-space accurate, no overflow), re-anchored every
/// 256 terms. About 15 sqrt(g) terms for rel_tol = 1e-12. `terms`, when given, receives the
/// number of terms summed.
double he_series_over_g(double g, double c, double rel_tol = kHeSeriesTolerance, int* terms = nullptr) noexcept;
/// g T(g, c): the series of eq. 78 itself, sum_{m>=1} g^m e^{-g}/(m! m) e^{-c/m}.
double he_series(double g, double c, double rel_tol = kHeSeriesTolerance, int* terms = nullptr) noexcept;

/// z0/sigma0 from eq. 81: the root x >= 0 of x exp(x^2/2) = f0, f0 = (K_i + K_r)/sqrt(8 pi).
/// Safeguarded Newton on ln x + x^2/2 = ln f0 inside the bracket [f0 e^{-1/2}, f0] (f0 <= 1)
/// or [sqrt(ln f0), max(1, sqrt(2 ln f0))] (f0 > 1); 0 for f0 <= 0, +inf for f0 = +inf.
double he_z0_over_sigma0(double f0) noexcept;

class HeTorrance final : public Model {
 public:
  /// sigma0, tau, lambda in micrometres; eta + ik the complex index (sign of k immaterial for
  /// |F|^2: the thesis's n = 1.6 - .2i is eta = 1.6, k = 0.2); a the uniform-diffuse albedo.
  HeTorrance(double sigma0, double tau, double lambda, double eta, double k, double a);

  std::string spec() const override;
  /// Isotropic; reciprocal (f is a symmetric expression, measured bit-exact); not plausible:
  /// rho_ud = a/pi is added to the surface reflection without taking its energy from it (a = 1
  /// gives albedo > 1), and even with a = 0 the Kirchhoff model exceeds 1 at oblique incidence
  /// for slightly rough, highly reflecting surfaces (measured albedo(f) + rho_s up to 1.039).
  Traits traits() const override { return {true, true, EnergyClass::not_plausible}; }
  /// rho_dd + a/pi (eqs. 71, 72); the specular delta is excluded (specular_reflectance).
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  std::optional<GlslF> glsl_mirror_reflectance() const override;
  /// Two peaks at mirror(fixed): the m = 1 term of eq. 78 (exp(-c): width lambda/(sqrt 2 pi tau)
  /// across, that over cos theta along) and, when g > 4, the m ~ g terms (sqrt(g) times wider).
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

  /// rho_dd alone (eq. 71), 1/sr.
  double directional_diffuse(const Vec3& i, const Vec3& j) const noexcept;
  /// rho_s = |F(theta_i)|^2 exp(-g(theta_i, theta_i)) S(theta_i)^2 (eqs. 73-74): the weight of
  /// the specular delta, i.e. the fraction of the flux from i reflected into mirror(i).
  double specular_reflectance(double cos_theta_i) const noexcept;
  /// The specular delta's weight, specular_reflectance: renders add it under skies and the
  /// Ganzfeld (Model::mirror_reflectance); f and the laws of f exclude it.
  double mirror_reflectance(double cos_theta) const noexcept override { return specular_reflectance(cos_theta); }
  /// Effective roughness sigma (micrometres) for the two cosines (eqs. 80-83).
  double effective_roughness(double cos_theta_i, double cos_theta_r) const noexcept;
  /// Shadowing S(theta) of one direction (eqs. 24-25 with Smith's exp(-a^2)).
  double shadowing(double cos_theta) const noexcept;
  /// S(theta)/cos theta, computed without the division (finite at theta = 90 deg).
  double shadowing_over_cos(double cos_theta, double sin_theta) const noexcept;

  double sigma0() const { return sigma0_; }
  double tau() const { return tau_; }
  double lambda() const { return lambda_; }

 private:
  double sigma_eff(double mu_i, double sin_i, double mu_r, double sin_r) const noexcept;
  double K(double mu, double sin_theta) const noexcept;

  double sigma0_, tau_, lambda_, eta_, k_, a_;
  double prefactor_;  // pi^2 tau^2 / (4 lambda^2), eq. 78
  double c_scale_;    // (pi tau / lambda)^2: c = c_scale_ |(i + j)_xy|^2
};

void register_he_torrance_models(std::vector<ModelInfo>& catalogue);

}  // namespace ganzfeld
