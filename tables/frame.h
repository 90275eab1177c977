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

/// The lobe frame's angles of the g coordinates (c_i, c_j, phi), clamped to their ranges, the
/// pole's components along (p, e1, e2) and j's cosine and sine (the formulas above).
struct LobeComponents {
  double theta_j, psi, beta, ip, ie1, ie2, cos_theta_j, sin_theta_j;
};
/// From cos phi and sin phi (only |sin phi| matters: the laws are even in phi).
LobeComponents lobe_components(PeakKind peak, double cos_theta_i, double cos_theta_j, double cos_phi,
                               double sin_phi) noexcept;

/// (theta_j, psi, beta) of the g coordinates (c_i, c_j, phi) (clamped to their ranges).
std::array<double, 3> lobe_coordinates(PeakKind peak, double cos_theta_i, double cos_theta_j, double phi) noexcept;

/// The directions (i, j), unit, at lobe coordinates (theta_j, psi, beta).
std::pair<Vec3, Vec3> lobe_directions(PeakKind peak, double theta_j, double psi, double beta) noexcept;

struct LobeFrame {
  PeakKind peak = PeakKind::mirror;
  double width = 0.0;  ///< radians
};

// The warped frame (docs/lut-format.md, "The warped frame", format version 4). In the gnomonic
// plane tangent at the peak p (k ∝ p + t1 e1 + t2 e2) the sky {k·i > 0} is the half plane
// t·ê > -cot psi, ê = (cos beta, sin beta): g is the lobe's mass on one side of a line, i.e. its
// marginal distribution along ê at cot psi (Koenderink & Pont's g as a "law of vignetting": the
// lobe vignetted by the sky's edge). A lobe centred at t = shift e1 with widths `along` (e1) and
// `across` (e2) has that marginal close to S(z), z = (cot psi + shift cos beta) / w(beta),
// w(beta)^2 = along^2 cos^2 beta + across^2 sin^2 beta, S(z) = (1 + z / sqrt(1 + z^2)) / 2 (the
// exact marginal of GGX's slope distribution, whose tails are algebraic). Multiplied through by
// |i⊥| = sin psi, with q = i·p + shift (i·e1) and r^2 = along^2 (i·e1)^2 + across^2 (i·e2)^2:
//   u_lobe = (1 + q / sqrt(q^2 + r^2)) / 2                     (no trigonometry, no division by 0)
//   offset = mix u_lobe + (1 - mix) (1 - psi / pi)
// The second term keeps a share of the nodes uniform in psi where a lobe's tails differ from S.
// Along offset, g / h is then nearly the identity, so a linear filter interpolates it well; the
// envelope A(theta_j) = (cos theta_j + sqrt(cos^2 theta_j + envelope^2 sin^2 theta_j)) / 2 (the
// mean k·n of a lobe of width `envelope` clipped by the horizon; 1 without an envelope) takes out
// the cos theta_j that h of a Koenderink–Pont lobe carries. The stored numbers are g / A.
//
// The third axis: where along >> across (GGX towards grazing: the reflected lobe is a thin arc,
// across ~ 2 alpha cos theta_j), g at a fixed offset turns within a few across/along radians of
// beta = pi/2, since the edge's direction in the plane where the lobe is round,
//   beta_w = atan2(across (i·e2), along (i·e1)),
// swings from 0 to pi there. Nodes uniform in beta_w alone starve beta near 0 and pi (the lobe is
// clipped by the horizon, not elliptical), so the axis is the blend
//   beta_axis = (1 - mu) beta + mu beta_w        (mu = beta_whitening; increasing in beta)
// which is beta where along = across (Koenderink–Pont lobes at moderate theta_j).

/// Fitting (one warp sample per theta_j node): the share of the offset axis that follows
/// the lobe, the factor on the quartile widths (a warp wider than the lobe's quartiles spreads a
/// Gaussian step over more nodes: measured on specular alpha = 8, 1000 and ggx roughness 0.3),
/// and theta_j's sinh_max width in lobe widths.
inline constexpr double kWarpMix = 0.85;
inline constexpr double kWarpWidthFactor = 1.5;
inline constexpr double kWarpedThetaWidths = 3.0;
/// The theta_j at which fit_warp compares g(psi = 0) / A with and without the envelope.
inline constexpr int kEnvelopeSamples = 17;
/// beta_whitening of fitted warps: measured on ggx roughness 0.3 at 25x49x17 (the worst lookup error
/// at 3000 points, half uniform in the law's coordinates, half in the axes: 0.029 with 0, 0.007 with
/// beta_w alone, 0.005 with 0.8; specular alpha = 100 unchanged).
inline constexpr double kWarpBetaWhitening = 0.8;

/// The warp parameters at theta_j (linear between the samples in theta_axis' index coordinate).
WarpSample warp_at(const Warp& warp, const Axis& theta_axis, double theta_j) noexcept;
/// warp_at at the index coordinate u of theta_j on the theta_j axis.
WarpSample warp_at_index(const Warp& warp, double u) noexcept;
/// A(theta_j) (1 without an envelope): (cos + sqrt(cos^2 + eps^2 sin^2)) / 2, from 1 at theta_j = 0
/// to eps / 2 at pi / 2, falling all the way when eps <= 1.
double warp_envelope(const Warp& warp, double theta_j) noexcept;
/// A(theta_j) from cos theta_j and sin theta_j.
double warp_envelope(const Warp& warp, double cos_theta_j, double sin_theta_j) noexcept;
/// The offset of a unit sky pole i with components (i·p, i·e1, i·e2) and angle psi to p.
double warped_offset(const WarpSample& at, double mix, double ip, double ie1, double ie2, double psi) noexcept;
/// The third axis' coordinate of a pole with components (i·e1, i·e2 >= 0) at beta = atan2(i·e2, i·e1).
double warped_beta(const WarpSample& at, double whitening, double ie1, double ie2, double beta) noexcept;
/// (theta_j, offset, beta axis) of the g coordinates (c_i, c_j, phi).
std::array<double, 3> warped_coordinates(PeakKind peak, const Warp& warp, const Axis& theta_axis, double cos_theta_i,
                                         double cos_theta_j, double phi) noexcept;
/// The directions (i, j) at warped coordinates: beta by bisection (the axis rises with it), then psi
/// by bisection (offset falls with psi).
std::pair<Vec3, Vec3> warped_directions(PeakKind peak, const Warp& warp, const Axis& theta_axis, double theta_j,
                                        double offset, double beta) noexcept;
/// The warp of `model`'s g: at each theta_j node of `theta_axis`, the quartiles of g along cot psi at
/// beta = 0, pi/2, pi (TOMS 748 root finding to 1e-9 in asinh cot psi, cubature at `tolerance`), relative to g's range
/// between psi = pi and 0: shift = half the distance of the medians at beta = pi and 0, along and across from the
/// quartile spreads (S(z) = 3/4 at z = 1/sqrt(3)) times kWarpWidthFactor, kept within [width/8, 8 width + 1] of the
/// hinted width; the envelope (the lobe's width or none) that makes g(psi = 0) / A smoother over kEnvelopeSamples
/// theta_j.
Warp fit_warp(const Model& model, const LobeFrame& frame, const Axis& theta_axis, double tolerance);

/// The lobe frame of a model's g from its mass hints for the law of vignetting (varying the
/// incident direction): the narrowest peak that sits at the mirror direction of j or at j at
/// every probed j, and its narrowest width over them. Nothing when no peak does (Lambert,
/// Minnaert, asperity: their g is smooth in the cosines frame or has no lobe to follow).
std::optional<LobeFrame> lobe_frame_of(const Model& model);

}  // namespace ganzfeld::tables
