// Kajiya's anisotropic reflection, its analytic case: a surface of parallel fibres (smooth
// cylinders) along the tangent t = +x.
//
// Kajiya ("Anisotropic Reflection Models", SIGGRAPH '85) derives reflection from a surface's
// microgeometry with the Kirchhoff approximation and, for a general microgeometry, tabulates the
// result numerically per surface (Walker 1999, ch. III "Kajiya": "he builds a lookup table that is
// used at run-time"): there is no formula to implement without a microgeometry and its table. The
// one microgeometry with a closed form is the cylinder, which Kajiya & Kay wrote down ("Rendering
// Fur with Three Dimensional Textures", SIGGRAPH '89, section 3.3): a smooth cylinder reflects a
// beam into the cone of directions that make the same angle with its axis as the beam (the
// tangential component along t is kept, k·t = -i·t), which they blur with a cosine power, and
// a Lambertian cylinder lit from i returns light in proportion to its width seen from i, sin(t, i):
//   radiance per unit beam irradiance = kd sin(t, i)/pi + ks cos^n(angle from j to the cone),
//   cos(angle from j to the cone) = sin(t, i) sin(t, j) - (t·i)(t·j)   (i, j both away from the
//                                                                       surface; <= 0: no highlight)
// The model, as Phong's (models/classic_models.h), gives radiance per unit irradiance across the
// beam, not on the surface: as a BRDF it is divided by i·n (floored at kGrazingCosFloor),
//   f = [kd sin(t, i)/pi + ks max(0, sin(t, i) sin(t, j) - (t·i)(t·j))^n] / (i·n).
// So it is neither reciprocal nor plausible, as the original intensity model is not.
#pragma once

#include <string>

#include "models/model.h"

namespace ganzfeld {

class Kajiya final : public Model {
 public:
  Kajiya(double kd, double ks, double n);
  std::string spec() const override;
  /// Anisotropic (fibres along x), not reciprocal (the 1/(i·n) and sin(t, i)), not plausible
  /// (albedo ~ 1/(i·n) at grazing incidence).
  Traits traits() const override { return {false, false, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  /// The highlight is the cone k·t = -fixed·t about the fibres, a circle through the horizon:
  /// seven points along its upper half, width 1/sqrt(n) (cos^n psi ~ exp(-n psi^2/2)); and, over
  /// incident directions, the layer k·n < kGrazingCosFloor where the floored 1/(k·n) makes
  /// (k·n) f fall to 0 (kGrazingLayer, models/classic_models.h).
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// cos of the angle from j to the cone of mirror directions of i about the fibres.
  static double cone_cosine(const Vec3& i, const Vec3& j) noexcept;

 private:
  double kd_, ks_, n_;
};

}  // namespace ganzfeld
