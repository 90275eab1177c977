// Schlick's inexpensive BRDF model (C. Schlick, "An Inexpensive BRDF Model for Physically-based
// Rendering", Computer Graphics Forum 13(3), Eurographics '94), the single ("homogeneous")
// material with parameters C (reflection factor at normal incidence), r (roughness) and p
// (isotropy), and its rational approximations.
//
// With u = i·h = |i + j|/2, t = h·n, v = i·n, v' = j·n and w = cos of the azimuth of h from the
// tangent T (the local x axis, the direction of the scratches):
//   f = S(u) [G(v) G(v') Z(t) A(w) + 1 - G(v) G(v')] / (4 pi v v'),
//   S(u) = C + (1 - C)(1 - u)^5                          (Schlick's Fresnel factor)
//   G(v) = v/(r - r v + v)                               (Smith's self-shadowing, rational)
//   Z(t) = r/(1 + r t^2 - t^2)^2                         (zenith: pi times GGX with alpha^2 = r)
//   A(w) = sqrt(p/(p^2 - p^2 w^2 + w^2))                 (azimuth: peaks where h is across T)
// The second term returns the light the microfacets shadow as a broad lobe (interreflection).
//
// The paper's own text was not among the sources we could read; the formulas above are as two
// readings of it agree (LuxRender's schlickbrdf.h, which implements exactly this with the second
// term as an option, and an extract of the paper), and differences are listed in docs/models.md.
//
// Correction (docs/errata.md, schlick.a.norm): the normalization the paper requires of a slope
// distribution, ∫∫ D cos alpha sin alpha d alpha d phi = pi, holds for Z alone but not for Z A
// unless p = 1: ∫ A d phi = 4 sqrt(p) K(sqrt(1 - p^2)) < 2 pi (K the complete elliptic integral
// of the first kind). We use A / a(p), a(p) = (2/pi) sqrt(p) K(sqrt(1 - p^2)) its mean over phi.
//
// Horizon: the first term's cosines cancel (G(v)/v = 1/(r - r v + v)); the second term's
// 1/(v v') is kept and its cosines floored at kGrazingCosFloor (models/classic_models.h).
#pragma once

#include <array>
#include <optional>
#include <string>

#include "models/model.h"

namespace ganzfeld {

namespace schlick {

/// S(u) = C + (1 - C)(1 - u)^5 for the cosine u of the angle of incidence on the facet.
double fresnel(double u, double C) noexcept;
/// G(v) = v/(r - r v + v).
double smith(double v, double r) noexcept;
/// Z(t) = r/(1 + r t^2 - t^2)^2; ∫ Z(t) t d omega = pi over the hemisphere.
double zenith(double t, double r) noexcept;
/// A(w) = sqrt(p/(p^2 - p^2 w^2 + w^2)) as printed.
double azimuth(double w, double p) noexcept;
/// The mean of the printed A over the azimuth, (2/pi) sqrt(p) K(sqrt(1 - p^2)); 1 at p = 1.
double azimuth_mean(double p) noexcept;
/// Schlick's rational approximation of the Phong lobe t^n (1994): t/(n - n t + t) for t > 0.
double rational_phong(double t, double n) noexcept;

}  // namespace schlick

class Schlick final : public Model {
 public:
  Schlick(double C, double r, double p);
  std::string spec() const override;
  /// Reciprocal (f is symmetric in i, j); isotropic only when p = 1; not plausible: the
  /// interreflection term's albedo grows as 1/(2 (i·n)) towards grazing incidence.
  Traits traits() const override { return {p_ == 1.0, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  /// The mirror direction with width sqrt(2 r) p (Z is a GGX lobe of alpha = sqrt(r); A narrows
  /// it to within p of the plane across T).
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// Schlick's sampling of the halfway vector, cos^2 theta = xi/(r - r xi + xi) (exact for Z)
  /// and phi = (pi/2) sqrt(p^2 xi'^2/(1 - xi'^2 + p^2 xi'^2)) from the bitangent, mirrored into
  /// the four quadrants (its density, derived exactly, only approximates A), i the reflection of
  /// j about h; with probability 1 - G(j·n) (within [0.05, 0.95]) a cosine draw instead.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;

  /// The density per steradian of the halfway-vector draw.
  double halfway_pdf(const Vec3& h) const noexcept;
  Vec3 sample_halfway(double xi_1, double xi_2) const noexcept;

 private:
  double probability_cosine(double mu_j) const noexcept;

  double C_, r_, p_;
  double a_mean_;  ///< schlick::azimuth_mean(p)
};

}  // namespace ganzfeld
