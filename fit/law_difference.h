// How a fit differs from its data under extended sources: the laws of Koenderink & Pont
// (integrate/laws.h) of both at a few geometries. A fit may match f pointwise to a small metric
// and still darken (h) or vignette (g) differently, because the laws weigh grazing directions the
// metrics leave out (θ > 80°) and integrate the whole lobe, tails included.
#pragma once

#include <string>
#include <vector>

#include "integrate/laws.h"

namespace ganzfeld::fit {

struct LawPoint {
  Law law = Law::h;
  double theta_i_deg = 0.0, theta_j_deg = 0.0, phi_deg = 0.0;  ///< the geometry (unused angles 0)
  Estimate data, fit;
};

struct LawDifference {
  std::vector<LawPoint> points;
  double max_g = 0.0, max_h = 0.0, max_a = 0.0;  ///< max |fit − data| per law over the points
  bool converged = true;                         ///< every integral converged
};

/// The geometries: h at θ_j ∈ {0, 30, 60, 80}°, a at θ_i ∈ {0, 30, 60, 80}°, g at (θ_i, θ_j, φ) ∈
/// {(30, 0, 0), (60, 45, 0), (60, 45, 180), (120, 30, 0)}° (a pole beyond the horizon last).
std::vector<LawPoint> law_geometries();

/// The laws of `data` and `fit` at law_geometries(), to absolute tolerance `tolerance`.
LawDifference law_difference(const Model& data, const Model& fit, double tolerance);
/// The same with the data's laws already computed (one data set, many fits): `data_points` is
/// law_difference's points for that data (only their `data` estimates are read).
LawDifference law_difference(const std::vector<LawPoint>& data_points, const Model& fit, double tolerance);
/// The data's laws alone (the `fit` estimates left empty).
std::vector<LawPoint> data_laws(const Model& data, double tolerance);

}  // namespace ganzfeld::fit
