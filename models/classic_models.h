// The classic catalogue: the analytic models of Walker's survey ("A Visualization System for
// Bidirectional Reflectance Distribution Functions", MSc thesis, U. Oregon 1999, chapter III and
// appendix D), each implemented from its original paper. Where the thesis's summary differs
// from the original, the original is implemented and the difference is noted in docs/models.md.
//
// Conventions as in models/model.h: local frame n = +z, i towards the source, j towards the eye,
// mu_i = i·n, mu_j = j·n; f in 1/sr; 0 strictly below the horizon; never NaN or Inf.
//
// Models whose printed formula diverges on the horizon (Phong's 1/mu_i, Ward's
// 1/sqrt(mu_i mu_j), Oren–Nayar's tan beta as both directions graze) are regularized by
// replacing the vanishing cosine by kGrazingCosFloor; the integrand (k·n) f differs from the
// printed one only on a layer of thickness kGrazingCosFloor at the horizon.
#pragma once

#include <string>
#include <vector>

#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

/// Smallest cosine used in a denominator that vanishes on the horizon (see above).
inline constexpr double kGrazingCosFloor = 1e-6;
/// The horizon layer (MassHints::horizon_layer) a model declares for the ramp of that floor: its
/// kink lies on the curve k·n = kGrazingCosFloor, and a cut at that very distance from the
/// horizon would touch it at one longitude and keep it in the gap next to the cut (0.4% of a
/// panel) for a long way on either side, where no node sees it (ward g at j·n = 1e-9, with its
/// kink at k·n = 1e-3 hinted at 1e-3: 1.8e-3 off with 9e-9 estimated). At twice the distance the
/// kink lies inside the panel along the horizon wherever it is within 60° of that longitude.
inline constexpr double kGrazingLayer = 2.0 * kGrazingCosFloor;

/// Plausibility needs the two reflectances to share one unit of energy (Walker: "the sum
/// rho_s + rho_d should be less than or equal to one"): checked where a model is made; throws
/// InputError naming both keys, their values and the rule.
void require_sum_at_most_one(const std::string& model, const char* a, double va, const char* b, double vb);
/// The parameter table entries shared by the Phong-type models: kd, ks in [0, 1], n in [1, 10000].
ParamInfo kd_param(double def);
ParamInfo ks_param(double def);
ParamInfo n_param(double def, const char* meaning);

// ---------------------------------------------------------------------------------------------
/// Exact unpolarized Fresnel reflectance of a smooth interface from air (index 1) into a medium
/// of complex index eta + i k, for the cosine of the angle of incidence on the interface
/// (Born & Wolf §13.4; as pbrt-v4 FrComplex): F = (|r_s|^2 + |r_p|^2)/2. At normal incidence
/// F = ((eta-1)^2 + k^2)/((eta+1)^2 + k^2).
double fresnel_complex(double cos_theta, double eta, double k) noexcept;

// ---------------------------------------------------------------------------------------------
/// The shape of Phong's lobe as a function of cos psi: the cosine power, or Schlick's rational
/// approximation of it (models/schlick.h), t/(n - n t + t).
enum class PhongLobe { cosine_power, schlick_rational };

/// Phong 1975, as a BRDF: the specular term is added to the *reflected intensity* without the
/// cos(theta_i) factor that multiplies the diffuse term, so as a BRDF
///   f = kd/pi + ks max(0, cos psi)^n / mu_i,   cos psi = mirror(i)·j.
/// Not reciprocal (the 1/mu_i), albedo unbounded at grazing incidence. With
/// PhongLobe::schlick_rational (`schlick-phong`, Walker's Figs. 17 and 19) cos^n psi is replaced by
/// Schlick's rational t/(n - n t + t), t = max(0, cos psi): equal at t = 0 and 1 with the same
/// slope n at t = 1, a lobe of about the same width (half maximum at t = n/(n + 1) against
/// 2^(-1/n)) and far heavier tails (t/n as t -> 0, against t^n).
class Phong final : public Model {
 public:
  Phong(double kd, double ks, double n, PhongLobe lobe = PhongLobe::cosine_power);
  std::string spec() const override;
  Traits traits() const override { return {true, false, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

 private:
  double lobe(double cos_psi) const noexcept;

  double kd_, ks_, n_;
  PhongLobe lobe_;
};

/// Lewis 1994 ("Making shaders more physically plausible"), the normalized Phong BRDF
///   f = kd/pi + ks (n+2)/(2 pi) max(0, cos psi)^n:
/// reciprocal; albedo kd + ks at normal incidence and less elsewhere.
class PhongLewis final : public Model {
 public:
  PhongLewis(double kd, double ks, double n);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

 private:
  double kd_, ks_, n_, C_;
};

/// Blinn 1977 halfway-vector lobe, f = kd/pi + ks C_bp(n) (h·n)^n, h = (i+j)/|i+j|, with C_bp
/// chosen so that the lobe's albedo at normal incidence is exactly 1 (closed form below).
class BlinnPhong final : public Model {
 public:
  BlinnPhong(double kd, double ks, double n);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

 private:
  double kd_, ks_, n_, C_;
};
/// 1/C_bp = 2 pi ∫_hemisphere (h·n)^n (k·n) dk at i = n
///        = 8 pi [2 (1 - 2^-(n+4)/2)/(n+4) - (1 - 2^-(n+2)/2)/(n+2)].
double blinn_phong_normalization(double n);

// ---------------------------------------------------------------------------------------------
enum class FacetDistribution { beckmann, gaussian };

/// Cook & Torrance 1981 (SIGGRAPH '81, "A reflectance model for computer graphics"):
///   f = kd/pi + ks F(i·h) D(delta) G / (pi mu_i mu_j),
///   G = min(1, 2 (n·h) mu_j/(j·h), 2 (n·h) mu_i/(j·h)),
///   D_beckmann = exp(-tan^2 delta / m^2) / (4 m^2 cos^4 delta)   (as printed in SIGGRAPH '81),
///   D_gaussian = c exp(-(delta/m)^2)  (the paper leaves c free; we take the c that gives it the
///                                      same projected-area normalization as D_beckmann).
/// Implemented in the equivalent form f_s = ks F D_n G / (4 mu_i mu_j) with the normalized
/// distribution ∫ D_n (h·n) dh = 1 (D_n = 4 D / pi).
class CookTorrance final : public Model {
 public:
  CookTorrance(FacetDistribution d, double kd, double ks, double m, double eta, double k);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// The normalized facet distribution D_n(cos delta), ∫ D_n (h·n) dh = 1.
  double D(double cos_delta) const noexcept;

 private:
  FacetDistribution d_;
  double kd_, ks_, m_, eta_, k_;
  double c_gauss_ = 0.0;  // normalization of the Gaussian distribution
};

// ---------------------------------------------------------------------------------------------
/// Ward 1992 ("Measuring and modeling anisotropic reflection", eq. 5a/5b):
///   f = rho_d/pi + rho_s exp(-tan^2 delta (cos^2 phi_h/ax^2 + sin^2 phi_h/ay^2))
///                        / (4 pi ax ay sqrt(mu_i mu_j)),
/// phi_h the azimuth of h from the local x axis (the tangent). Isotropic: ax = ay = alpha.
class Ward final : public Model {
 public:
  Ward(double rho_d, double rho_s, double alpha_x, double alpha_y, bool anisotropic);
  std::string spec() const override;
  Traits traits() const override { return {!anisotropic_, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// Ward's sampling (1992, section 5.3, eq. 6–7 and 9–10), with the density B. Walter derived
  /// for it ("Notes on the Ward BRDF", 2005): the halfway vector from
  ///   phi_h = atan2(alpha_y sin 2 pi u2, alpha_x cos 2 pi u2),
  ///   tan^2 delta = -log u1 / (cos^2 phi_h / alpha_x^2 + sin^2 phi_h / alpha_y^2),
  /// i the reflection of j about it, pdf(i) = exp(-tan^2 delta (...)) / (4 pi alpha_x alpha_y
  /// cos^3 delta (i·h)); the diffuse part by cosine, chosen with probability rho_d/(rho_d + rho_s).
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;

 private:
  double rho_d_, rho_s_, alpha_x_, alpha_y_;
  bool anisotropic_;
};

// ---------------------------------------------------------------------------------------------
/// Oren & Nayar 1994 ("Generalization of Lambert's reflectance model", SIGGRAPH '94, eqs. 8
/// [C1, C2, C3] and 11 [L2, interreflection]); f = (L1 + L2)/(E0 cos theta_i).
class OrenNayar final : public Model {
 public:
  OrenNayar(double sigma, double rho);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  std::optional<GlslF> glsl_f() const override;

 private:
  double sigma_, rho_;
};

// ---------------------------------------------------------------------------------------------
/// Lafortune et al. 1997 ("Non-linear approximation of reflectance functions", eq. 4), one
/// generalized cosine lobe plus Lambert:
///   f = kd/pi + max(0, Cx ix jx + Cy iy jy + Cz iz jz)^n.
class Lafortune final : public Model {
 public:
  struct Lobe {
    double C_x, C_y, C_z, n;
  };
  Lafortune(double kd, double C_x, double C_y, double C_z, double n);
  /// Several lobes, f = kd/pi + sum_k max(0, Cx ix jx + Cy iy jy + Cz iz jz)^n_k (eq. 4 summed),
  /// named by `spec` (a preset such as lafortune-paint:channel=2).
  Lafortune(double kd, std::vector<Lobe> lobes, std::string spec);
  std::string spec() const override;
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

 private:
  double kd_;
  std::vector<Lobe> lobes_;
  std::string preset_;  ///< empty for the one-lobe model with its parameters in the spec
};

/// Lafortune, Foo, Torrance & Greenberg 1997 (SIGGRAPH '97), their three-lobe fit to measured
/// blue (latex) paint, per RGB channel: the paint of Walker's Figure 35 (the thesis shows the
/// lobe but prints no coefficients). Coefficients as published with the paper's data and
/// reproduced in pbrt (1st ed.) "bluepaint"; Cx = Cy (isotropic).
ModelPtr lafortune_paint(int channel);

// ---------------------------------------------------------------------------------------------
/// Hapke 1963 ("A theoretical photometric function for the lunar surface") in the form of
/// Walker's eqs. III.27-29 (after Ellis 1994, as used in Beard–Maxwell's volumetric term):
///   f = rho S(alpha) B(alpha, g) / (pi (mu_i + mu_j)),   alpha = arccos(i·j) the phase angle,
///   B = 2 - tan(alpha)/(2g) (1 - e^{-g/tan alpha}) (3 - e^{-g/tan alpha}) for alpha <= pi/2,
///       1 beyond (the shadow-hiding opposition surge, Hapke's retroreflection function),
///   S = 1 (isotropic), 4/9 (1 - cos(alpha)/2)^2 (forward), (sin a + (pi - a) cos a)/pi (back:
///       the Lambert-sphere phase law; the thesis prints "-" for "+", which goes negative).
enum class HapkePhase { isotropic = 0, forward = 1, back = 2 };
class Hapke final : public Model {
 public:
  Hapke(double rho, double g, HapkePhase phase);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// The retroreflection function B(alpha, g) for the phase angle's cosine and tangent.
  static double B(double tan_alpha, double cos_alpha, double g) noexcept;

 private:
  double rho_, g_;
  HapkePhase phase_;
};

}  // namespace ganzfeld
