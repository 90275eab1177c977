// Ashikhmin & Shirley's anisotropic Phong BRDF ("An Anisotropic Phong BRDF Model", Journal of
// Graphics Tools 5(2), 2000, 25-32), with its importance sampling.
//
//   f = rho_s + rho_d,  h = (i + j)/|i + j|,  k·h = i·h = j·h = |i + j|/2,
//   rho_s = sqrt((n_u + 1)(n_v + 1))/(8 pi) (h·n)^e(h) / ((k·h) max(i·n, j·n)) F(k·h),
//   e(h)  = (n_u (h·u)^2 + n_v (h·v)^2)/(1 - (h·n)^2),
//   F(x)  = R_s + (1 - R_s)(1 - x)^5                                        (Schlick's Fresnel)
//   rho_d = 28 R_d/(23 pi) (1 - R_s)(1 - (1 - i·n/2)^5)(1 - (1 - j·n/2)^5).
//
// Sampling (the paper's Monte Carlo section): the halfway vector h from
//   phi = atan(sqrt((n_u + 1)/(n_v + 1)) tan(pi xi_1/2))   (one quadrant; the others mirrored),
//   cos theta = (1 - xi_2)^(1/(n_u cos^2 phi + n_v sin^2 phi + 1)),
// whose density is p_h(h) = sqrt((n_u + 1)(n_v + 1))/(2 pi) (h·n)^e(h)
// exactly, and i = 2 (j·h) h - j with p(i) = p_h(h)/(4 (j·h)); the diffuse part by cosine.
//
// Tangent frame: u = +x (n_u along the tangent), v = +y, n = +z. Isotropic when n_u = n_v.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "models/model.h"

namespace ganzfeld {

class AshikhminShirley final : public Model {
 public:
  AshikhminShirley(double rd, double rs, double nu, double nv);
  std::string spec() const override;
  /// Reciprocal (bit-exact: f is symmetric in i and j); isotropic only when n_u = n_v;
  /// plausible as measured (docs/plausibility.md): the specular term reflects at most F (its
  /// sampling weight is F (i·n)/max(i·n, j·n) <= F) and the diffuse term (1 - R_s) R_d (1 - (1 -
  /// i·n/2)^5); their sum stayed below 1 on every parameter corner and incidence tried (largest
  /// 0.9996, R_s = 1, n_u = n_v = 10000, normal incidence), though no bound is proved.
  Traits traits() const override { return {nu_ == nv_, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  /// The mirror direction, width 2/sqrt(max(n_u, n_v) + 1) along the plane of n and the fixed
  /// direction (as blinn-phong: the halfway lobe (h·n)^e ~ exp(-e delta^2/2), psi ~ 2 delta),
  /// (fixed·n) times thinner across, floored at 1e-3 of it.
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// With probability w_d/(w_d + w_s), w_d = R_d (1 - R_s), w_s = R_s + (1 - R_s)/21 (the
  /// cosine-weighted mean of F), a cosine draw; else the paper's halfway-vector draw. Draws
  /// reflected below the horizon fail.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;

  /// The density p_h of the paper's halfway-vector draw (per steradian of h).
  double halfway_pdf(const Vec3& h) const noexcept;
  /// The halfway vector drawn from two uniform numbers by the paper's formulas.
  Vec3 sample_halfway(double xi_1, double xi_2) const noexcept;
  /// rho_d alone.
  double diffuse(const Vec3& i, const Vec3& j) const noexcept;

 private:
  double exponent(const Vec3& h) const noexcept;
  double probability_diffuse() const noexcept;

  double rd_, rs_, nu_, nv_;
  double norm_;  ///< sqrt((n_u + 1)(n_v + 1))
};

}  // namespace ganzfeld
