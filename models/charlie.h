// The "Charlie" sheen BRDF of Estevez & Kulla ("Production Friendly Microfacet Sheen BRDF",
// Sony Pictures Imageworks, 2017) with the visibility term of Neubelt & Pettineo ("Crafting a
// Next-Gen Material Pipeline for The Order: 1886", SIGGRAPH 2013 course), as Filament's cloth
// model combines them ("Physically Based Rendering in Filament", section "Cloth model"):
//
//   f(i, j) = D(h) V(i, j),  D = (2 + 1/α) sin^(1/α) θ_h / (2π),
//                            V = 1/(4 (i·n + j·n − (i·n)(j·n))),
//
// h = (i + j)/|i + j|, θ_h its angle from n. No Fresnel. D is an inverted-Gaussian-like
// distribution whose normals crowd towards the surface plane (fibres), ∫ D cos θ_h dω_h = 1.
// Estevez & Kulla's own Λ-based shadowing (their fitted curves) is not used. Sampling: the
// default cosine-weighted draw; f is bounded away from the both-grazing corner, so the weight
// π f has finite variance.
#pragma once

#include <string>

#include "models/model.h"

namespace ganzfeld {

class Charlie final : public Model {
 public:
  explicit Charlie(double alpha) : alpha_(alpha) {}
  std::string spec() const override;
  /// Not plausible: the visibility term lets the albedo exceed 1 towards grazing for small α
  /// (measured: 1.0013 at 89.9° for α = 0.2, 12.6 on the horizon for α = 0.001; docs/models.md).
  Traits traits() const override { return {true, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// The distribution for sin²θ_h: (2 + 1/α)(sin²θ_h)^(1/(2α))/(2π).
  double D(double sin2_theta_h) const noexcept;

 private:
  double alpha_;
};

}  // namespace ganzfeld
