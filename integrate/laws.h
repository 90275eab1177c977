// The laws of K&P computed by cubature for any model, each with its error estimate:
//   g(i, j) = ∫_{k·n>0, k·i>0} (k·n) f(k, j) dk    law of vignetting (sky with pole i, i·n in [-1,1])
//   h(j)    = ∫_{k·n>0} (k·n) f(k, j) dk            law of darkening (Ganzfeld)
//   a(i)    = ∫_{k·n>0} (k·n) f(i, k) dk            albedo
//   r       = (1/pi) ∫ (i·n) a(i) di                double-diffuse reflectance
// Domains are parametrized exactly: the lune {k·n > 0} ∩ {k·i > 0} is rotated about
// its edge axis e = n×i/|n×i| into the rectangle t ∈ [-pi/2, pi/2] (latitude from the plane ⊥ e)
// × phi ∈ [theta_i - pi/2, pi/2] (longitude from n towards i), with weight cos t; the hemisphere
// is the lune with i = n. No indicator functions anywhere.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "integrate/cubature.h"
#include "models/model.h"

namespace ganzfeld {

enum class Law { f, g, h, a, r };
const char* to_string(Law law);
/// Throws InputError for anything but f, g, h, a, r.
Law parse_law(const std::string& text);

Estimate vignetting(const Model& model, const Vec3& i, const Vec3& j, const CubatureOptions& options);
Estimate darkening(const Model& model, const Vec3& j, const CubatureOptions& options);
Estimate albedo(const Model& model, const Vec3& i, const CubatureOptions& options);
Estimate double_diffuse(const Model& model, const CubatureOptions& options);

/// Any law for directions i, j in the local frame (unused ones are ignored); f is exact
/// (error 0, one evaluation).
Estimate evaluate_law(const Model& model, Law law, const Vec3& i, const Vec3& j, const CubatureOptions& options);

/// The lune {k·n > 0} ∩ {k·pole > 0} as the rectangle t ∈ [-pi/2, pi/2] × phi ∈ [phi_lo, pi/2]:
/// k = cos t (cos phi n + sin phi u) + sin t e, dk = cos t dt dphi. With pole = n it is the
/// hemisphere, oriented so that the plane of n and `fixed` lies at t = 0.
struct Lune {
  Vec3 e, u;           ///< edge axis and the tangent towards the pole
  double phi_lo = 0;   ///< theta_pole - pi/2
  bool empty = false;  ///< pole at the nadir
  Vec3 direction(double t, double phi) const;
};
Lune lune(const Vec3& pole, const Vec3& fixed);
/// The engine's initial grid on that rectangle, from the model's mass hints (lines at each
/// peak and ±2 widths; at delta and 4 delta from the horizon).
std::array<std::vector<double>, 2> lune_cuts(const Model& model, const Lune& lune, const Vec3& fixed, Varying varying);

/// Unit direction from polar angle theta (from n) and azimuth phi, radians.
Vec3 direction(double theta, double phi);
/// Unit direction with cos theta = `cos_theta` (no acos round trip, exact at 0 and ±1) and azimuth phi.
Vec3 direction_from_cos(double cos_theta, double phi = 0.0);

}  // namespace ganzfeld
