// The lobe frame of g tables (docs/lut-format.md, "Axes", version 2): coordinates that follow
// the sharp structure of g instead of the normal.
//
// Why: g(i, j) = ∫_{k·n>0, k·i>0} (k·n) f(k, j) dk. For a lobe of width w about a peak p(j) (the
// mirror direction of j for specular, j itself for backscatter), g as a function of i is the part
// of the lobe on the sky's side of the great circle k·i = 0: it steps from the whole lobe to
// nothing as that circle sweeps over p, i.e. as the angle psi between i and p crosses pi/2, over
// a band of width ~w, and is otherwise smooth on the scale of the hemisphere. In (i·n, j·n, phi)
// the step is a thin curved sheet, so linear axes need ~1/w nodes on every axis; in
//   theta_j = polar angle of j,  psi = angle(i, p(j)),  beta = azimuth of i about p(j)
// the step lies along one axis (psi) and the sinh mapping psi = pi/2 + w sinh(v) spreads it over
// a fixed number of nodes, whatever w.
//
// With j = (sin theta_j, 0, cos theta_j) (isotropy: only the relative azimuth of i and j matters),
// s = -1 (mirror) or +1 (retro):
//   p  = (s sin theta_j, 0, cos theta_j)    the peak
//   e1 = (-s cos theta_j, 0, sin theta_j)   perpendicular to p in the plane of n and p, e1·n >= 0
//   e2 = (0, 1, 0)
//   i  = cos psi p + sin psi (cos beta e1 + sin beta e2)
// and, from (c_i, c_j, phi) = (i·n, j·n, relative azimuth) with s_i = sqrt(1 - c_i^2),
// s_j = sqrt(1 - c_j^2), i = (s_i cos phi, s_i sin phi, c_i):
//   i·p  = s s_i s_j cos phi + c_i c_j
//   i·e1 = -s s_i c_j cos phi + c_i s_j
//   i·e2 = s_i sin phi  (>= 0: g is even in phi, so beta folds into [0, pi])
//   theta_j = atan2(s_j, c_j),  psi = atan2(hypot(i·e1, i·e2), i·p),  beta = atan2(i·e2, i·e1).
#pragma once

#include <array>
#include <optional>
#include <utility>

#include "models/model.h"
#include "tables/table.h"

namespace ganzfeld::tables {

/// (theta_j, psi, beta) of the g coordinates (c_i, c_j, phi) (clamped to their ranges).
std::array<double, 3> lobe_coordinates(PeakKind peak, double cos_theta_i, double cos_theta_j, double phi) noexcept;

/// The directions (i, j), unit, at lobe coordinates (theta_j, psi, beta).
std::pair<Vec3, Vec3> lobe_directions(PeakKind peak, double theta_j, double psi, double beta) noexcept;

struct LobeFrame {
  PeakKind peak = PeakKind::mirror;
  double width = 0.0;  ///< radians
};

/// The lobe frame of a model's g from its mass hints for the law of vignetting (varying the
/// incident direction): the narrowest peak that sits at the mirror direction of j or at j at
/// every probed j, and its narrowest width over them. Nothing when no peak does (Lambert,
/// Minnaert, asperity: their g is smooth in the cosines frame or has no lobe to follow).
std::optional<LobeFrame> lobe_frame_of(const Model& model);

}  // namespace ganzfeld::tables
