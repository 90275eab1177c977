// The Koenderink–Pont lobes ("Material Properties and Extended Sources for Surface Rendering",
// section "Generic, Simple, Analytic BRDFs"), their normalization constants and the closed forms
// printed in the paper. Printed forms are kept verbatim (`*_printed`) next to our corrected
// forms; `ganzfeld verify` decides which hold (docs/errata.md).
//
// Notation: mu_i = i·n, mu_j = j·n, c = i·n for the sky pole of the law of vignetting.
#pragma once

#include "models/model.h"

namespace ganzfeld {

// ---------------------------------------------------------------------------------------------
class Lambert final : public Model {
 public:
  std::string spec() const override { return "lambert"; }
  Traits traits() const override { return {true, true, EnergyClass::conserving}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
};
namespace lambert {
double g(double c);  // K&P: g_L = (1 + i·n)/2; h_L = a_L = r_L = 1
}

// ---------------------------------------------------------------------------------------------
/// f_d = C_d ((i·n)(j·n))^xi, C_d = (2 + xi)/(2 pi)   (K&P, "Bulk Scattering").
class Minnaert final : public Model {
 public:
  explicit Minnaert(double xi);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  double xi() const { return xi_; }

 private:
  double xi_, C_d_;
};
namespace minnaert {
double C_d(double xi);
double g_xi1_printed(double c, double mu_j);
double g_hyp2f1_printed(double c, double mu_j, double xi);
double g_betainc_printed(double c, double mu_j, double xi);
double g(double c, double mu_j, double xi);  // corrected, docs/errata.md
double h(double mu_j, double xi);            // printed h_d = (j·n)^xi
double a(double mu_i, double xi);            // printed a_d = (i·n)^xi
double r(double xi);                         // printed r_d = 2/(2 + xi)
}  // namespace minnaert

// ---------------------------------------------------------------------------------------------
/// f_s = C_s ((1 + k·j)/2)^alpha with k = 2(i·n)n - i   (K&P, "Specular reflection").
class Specular final : public Model {
 public:
  explicit Specular(double alpha);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  double alpha() const { return alpha_; }
  double C_s() const { return C_s_; }

 private:
  double alpha_, C_s_;
};
namespace specular {
double C_s_printed(double alpha);  // (1+a)(2+a) / (2 pi (2a + 2^-a))
double a_alpha1_printed(double mu_i);
double a_alpha8_printed(double mu_i);
}  // namespace specular

/// Largest constant C for which C·((1 + x·j)/2)^alpha has albedo <= 1, assuming the albedo
/// peaks at normal incidence (checked numerically by `verify`): at i = n the lobe is centred on
/// n for both the specular and the backscatter lobe, and
/// 1/C = 2 pi ∫_0^1 mu ((1+mu)/2)^alpha dmu = 2 pi (2 alpha + 2^-alpha) / ((alpha+1)(alpha+2)).
double cosine_power_lobe_normalization(double alpha);

// ---------------------------------------------------------------------------------------------
/// f_b = C_b ((1 + i·j)/2)^alpha   (K&P, "Backscattering").
class Backscatter final : public Model {
 public:
  explicit Backscatter(double alpha);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  double alpha() const { return alpha_; }
  double C_b() const { return C_b_; }

 private:
  double alpha_, C_b_;
};
namespace backscatter {
double C_b_printed(double alpha);  // 6 / (5 pi 2^alpha)
double C_b(double alpha);          // corrected, docs/errata.md
/// Printed g_b for alpha = 1 in K&P's angles: i·n = cos theta, j·n = sin eta sin zeta,
/// [i,j,n] = -cos zeta sin theta. Takes i and j in the local frame with i at azimuth 0.
double g_alpha1_printed(const Vec3& i, const Vec3& j);
double g_alpha1(const Vec3& i, const Vec3& j);  // corrected, docs/errata.md
double h_alpha1_printed(double mu_j);           // (3 + 2 j·n)/5
}  // namespace backscatter

// ---------------------------------------------------------------------------------------------
/// f_pb = C_pb (1 + i·j)^alpha / ((i + j)·n), C_pb = (1 + alpha)/(2^(1+alpha) pi), integer
/// alpha >= 2   (K&P, "Backscattering", the perfect backscatterer).
class PerfectBackscatter final : public Model {
 public:
  explicit PerfectBackscatter(int alpha);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  int alpha() const { return alpha_; }
  /// C_pb 2^alpha = (1 + alpha)/(2 pi): f = this × ((1 + i·j)/2)^alpha / ((i + j)·n).
  double C_pb_times_2_pow_alpha() const { return C_pb_times_2_pow_alpha_; }

 private:
  int alpha_;
  double C_pb_times_2_pow_alpha_;  // (1+alpha)/(2 pi): avoids 2^alpha overflow for alpha > 1023
};
namespace perfect_backscatter {
double C_pb_printed(double alpha);
double retro_radiance(double alpha);  // (i·n) f(i, i) = (1 + alpha) / (4 pi) for every i
}  // namespace perfect_backscatter

// ---------------------------------------------------------------------------------------------
/// f_a = C_a (1 - (i·n)(j·n))^alpha, C_a = 1/pi   (K&P, "Asperity Scattering").
class Asperity final : public Model {
 public:
  explicit Asperity(double alpha);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  double alpha() const { return alpha_; }

 private:
  double alpha_;
};
namespace asperity {
double C_a_printed();
double g_alpha1_printed(double c, double mu_j);
double g_alpha1(double c, double mu_j);  // corrected, docs/errata.md
double h_alpha1_printed(double mu_j);    // 1 - 2(j·n)/3
}  // namespace asperity

/// pi - arccos(c) + c sqrt(1 - c^2): the lune moment 3/2 ∫_lune (k·n)^2 dk that recurs in
/// K&P's g_d (xi = 1) and g_a.
double lune_moment_2(double c);

}  // namespace ganzfeld
