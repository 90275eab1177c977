// The GGX (Trowbridge–Reitz) microfacet BRDF with Smith masking-shadowing, and the free
// functions of its microfacet distribution.
//
//   f(i, j) = F(i·h) D(h) G2(i, j) / (4 (i·n)(j·n)),  h = (i + j)/|i + j|
//
// Sources:
//   Trowbridge & Reitz 1975 (JOSA 65(5)): the distribution of ellipsoidal facets;
//   Walter, Marschner, Li & Torrance 2007 ("Microfacet Models for Refraction through Rough
//     Surfaces", EGSR): the name GGX, D eq. 33, G1 eq. 34, the BRDF eq. 20, the reflection
//     Jacobian dω_h/dω_i = 1/(4 i·h) eq. 14;
//   Heitz 2014 ("Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
//     JCGT 3(2)): the anisotropic distribution and its Smith Λ (eq. 80 projected roughness,
//     eq. 86 Λ), the separable G2 = G1(i) G1(j) and the height-correlated
//     G2 = 1/(1 + Λ(i) + Λ(j)) of section 6;
//   Heitz 2018 ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4)): the density of
//     visible normals D_j(m) = G1(j) max(0, j·m) D(m)/(j·n) and its exact sampling (appendix A);
//   Schlick 1994 (Computer Graphics Forum 13(3)): F = f0 + (1 − f0)(1 − i·h)^5.
//
// Tangent frame: alpha_x along the local +x axis, alpha_y along +y (n = +z).
#pragma once

#include <array>
#include <optional>
#include <string>

#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

namespace ggx {

/// Roughness along the tangent (x) and the bitangent (y); isotropic when they are equal.
struct Alpha {
  double x = 0.5, y = 0.5;
};

/// D(m) = 1 / (pi alpha_x alpha_y (m_x²/alpha_x² + m_y²/alpha_y² + m_z²)²) for a unit m with
/// m·n > 0 (0 otherwise): Heitz 2014's anisotropic GGX; for alpha_x = alpha_y = alpha it is
/// Walter eq. 33, alpha²/(pi (1 + (alpha² − 1) cos²θ_m)²). ∫ D(m)(m·n) dm = 1.
double D(const Vec3& m, Alpha a) noexcept;
/// sqrt(w_z² + alpha_x² w_x² + alpha_y² w_y²) for a unit w: (w·n)(1 + 2Λ(w)), the term every
/// Smith expression below is written with (Heitz 2014 eq. 80 and 86). Finite on the horizon.
double projected_root(const Vec3& w, Alpha a) noexcept;
/// Smith's Λ(w) = (−1 + sqrt(1 + alpha_w² tan²θ_w))/2 (Heitz 2014 eq. 86); +inf on the horizon.
double Lambda(const Vec3& w, Alpha a) noexcept;
/// G1(w) = 1/(1 + Λ(w)) = 2(w·n)/((w·n) + projected_root(w)) (Walter eq. 34 when isotropic).
double G1(const Vec3& w, Alpha a) noexcept;

/// Which Smith masking-shadowing function G2 (Heitz 2014, section 6).
enum class G2Form { height_correlated = 0, separable = 1 };
/// G2(i, j)/(4 (i·n)(j·n)), the "visibility", in a form that stays finite when one direction
/// grazes: height-correlated 1/(2 (j·n) r(i) + 2 (i·n) r(j)), separable 1/(((i·n) + r(i))((j·n)
/// + r(j))), r = projected_root. 0 where both directions graze and it has no limit.
double visibility(const Vec3& i, const Vec3& j, Alpha a, G2Form form) noexcept;

/// Heitz 2018's density of normals visible from w: G1(w) max(0, w·m) D(m)/(w·n); a
/// probability density over the hemisphere of m.
double D_visible(const Vec3& w, const Vec3& m, Alpha a) noexcept;
/// A normal drawn with density D_visible(w, ·) from two uniform numbers (Heitz 2018, appendix
/// A): w is stretched to the configuration where the facets form a hemisphere (section 3.2),
/// a point is drawn uniformly on the projected half-disk (4.2) and lifted (4.3), and the normal
/// is stretched back (3.4). Requires w·n > 0.
Vec3 sample_visible_normal(const Vec3& w, Alpha a, double u1, double u2) noexcept;

}  // namespace ggx

/// ggx: the microfacet BRDF above. Fresnel is Schlick's with f0 (f0 = 1: F = 1, the white
/// furnace). Importance sampling of i for j: a visible normal m for j, i the reflection of j
/// about m, pdf(i) = D_visible(j, m)/(4 j·m) = G1(j) D(m)/(4 j·n); draws reflected below the
/// horizon fail (the energy single scattering loses).
class Ggx final : public Model {
 public:
  Ggx(ggx::Alpha alpha, double f0, ggx::G2Form g2);
  std::string spec() const override;
  /// The parameters of its canonical spec: alpha (or alpha_x and alpha_y), f0, g2.
  ParamValues parameters() const;
  Traits traits() const override { return {alpha_.x == alpha_.y, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;
  ggx::Alpha alpha() const { return alpha_; }
  /// GLSL statements that set `float ggx_value` to f(i, j) above the horizon (Ggx::glsl_f and
  /// ggx-ms's, models/ggx_ms.cpp); they declare s, len, m and the visibility's names too.
  std::string glsl_single_scattering() const;

 private:
  ggx::Alpha alpha_;
  double f0_;
  ggx::G2Form g2_;
};

}  // namespace ganzfeld
