// Poulin & Fournier 1990 ("A model for anisotropic reflection", SIGGRAPH '90, Computer Graphics
// 24(4) 273-282), additive cylinders; Walker 1999 (MSc thesis, U. Oregon), ch. III
// "Poulin-Fournier" (eqs. III.19-III.21) and appendix D (the pseudo-code for theta_M, theta_s, f_s).
//
// The surface. Parallel cylinders of unit radius along the tangent (local +x), centres a distance
// d apart, half-buried in a floor at height h above their axes (h in [0, 1]). Everything that
// shadows or hides depends only on the projections of i and j on the cross-section (the y-z
// plane). In that plane a cylinder's exposed arc is psi in [-theta_M, theta_M], psi the angle of
// its normal N(psi) = (0, sin psi, cos psi) from n, towards +y; between two cylinders lies a floor
// of width w:
//   phi_h = acos h,  phi_d = asin(d/2) (pi/2 for d >= 2),  theta_M = min(phi_d, phi_h),
//   w = max(d - 2 sqrt(1 - h^2), 0)                                       (app. D).
// A direction k projects to the side s = sign(k_y) and the elevation beta = atan2(k_z, |k_y|),
// Walker's theta_L = s (pi/2 - beta). Its "front" — the part of a period it lights (k = i) or
// sees (k = j) — is, for s = +1 (mirror for s = -1):
//   beta >= theta_M:  the whole arc and the whole floor;
//   else              arc psi in [-beta, min(theta_s, theta_M)] (self-shadow at -beta), where the
//                     neighbour's shadow line (tangent at its terminator) meets the arc at
//                     theta_s = theta_L + asin(d cos theta_L - 1) = 2 asin(sqrt(d sin(beta)/2)) - beta,
//                     or misses it (theta_s = pi/2) when 1/cos theta_L < d - 1;
//                     floor [0, w - f_s], the cylinder on the +y side shadowing
//                     f_s = min(1/cos theta_L - sqrt(1 - h^2) - h tan theta_L, w)
//                         = min(2 sin^2((beta - theta_M)/2)/sin beta, w)   (app. D; its max(., 0)
//                     is automatic).
// The right-hand forms are the thesis's, rewritten in beta so that they stay accurate at grazing
// (theta_L -> 90 deg); all were checked against 2-D ray casting (tests).
//
// The BRDF. Poulin & Fournier shade the visible and illuminated part of the arc and of the floor
// with a local model and weight them by their lengths projected on the mean plane along the eye
// (eqs. III.19-III.21: I_ref = (I_arc l_vi + I_floor f_vi)/(l_v + f_v)). The projected length of
// an arc element is dl = (N.j)/(n.j) dpsi, and l_v + f_v = d exactly (the visible pieces of one
// period tile the mean plane as seen from the eye; tested). With radiance E0 f_mu(N; i, j) (N.i)
// from each lit point and the BRDF f = L/(E0 n.i):
//   f(i, j) = [ ∫_{arc_vi} f_mu(N(psi); i, j) (N.i)(N.j)/((n.i)(n.j)) dpsi + f_vi f_mu(n; i, j) ] / d,
// arc_vi = front(i) ∩ front(j) on the arc, f_vi = the overlap of the two floor intervals. With
// u_k = s_k psi + beta_k, (N.k)/(n.k) = sin(u_k)/sin(beta_k) (no division by a vanishing
// projection). The local model f_mu is the catalogue's blinn-phong, kd/pi + ks C(n) (N.h)^n with
// h the halfway vector (Poulin & Fournier's Phong-type shading with the (N.H)^n highlight, in the
// BRDF form and normalization of models/classic_models.h BlinnPhong): so d = 0 or h = 1 gives
// exactly blinn-phong (Lambert kd/pi when ks = 0). The arc integrals are closed forms: the
// diffuse one a trigonometric polynomial (arc_cosine_product below), the specular one incomplete
// beta functions (cos_power_integral): N.h = r_h cos(psi - theta_H), and (N.i)(N.j) is
// A + B cos 2t + C sin 2t in t = psi - theta_H.
//
// f is symmetric in (i, j) term by term (reciprocal), non-negative, and its albedo is at most the
// local model's (each lit point reflects at most its local albedo, and what one direction lights
// projects to exactly d): plausible when kd + ks <= 1. Measured in tests/poulin_fournier_test.cpp.
//
// Grazing: the elevation beta of a projection is floored at kGrazingCosFloor (1e-6 rad): f grows
// like beta^{-1/2} when both directions graze from the same side (only the tops of the cylinders
// are lit and seen, and their normals lean towards both), so it is bounded by ~1e3 f_mu there.
//
// Creases (MassHints::crease_longitudes). f depends on the varying direction k through its
// projection (s_k, beta_k), i.e. its longitude about +x, phi = atan2(-k_y, k_z) = -theta_k, and
// smoothly through the halfway vector. f is continuous (no jumps: measured); its derivative
// jumps where an end of the intersection of the two fronts switches from one function of beta_k
// to another, and only its second derivative where the moving end is a terminator (the integrand
// sin(u_k) vanishes there) — listed too, as C1 creases (PfCrease::kink = false):
//   - beta_k = theta_M: the terminator of k enters the arc and its floor shadow starts (C1:
//     f_s and theta_M - theta_s grow quadratically);
//   - f_s(beta_k) = w, i.e. theta_s(beta_k) = theta_M: the floor is fully shadowed and the
//     neighbour's shadow reaches the arc (with a floor only; a kink);
//   - the limits of k meet the fixed direction's: beta_k = c (C1) or theta_s(beta_k) = c (a kink
//     unless c is the fixed direction's terminator), c = -arc_lo or arc_hi of the fixed front;
//     f_s(beta_k) = g for the fixed floor limits g (kinks).
// The first two are listed only when the fixed front reaches the end of the period they act on
// (else f does not change there). Each equation theta_s(beta) = c or f_s(beta) = g is
// a sin(beta) + b cos(beta) = 1 (solved in closed form, each root checked against the function).
// The branch 1/cos theta_L < d - 1 is not a crease (theta_s is continuous there and clamped by
// theta_M anyway), nor is the change of side at theta_k = 0 (III.20's "same side of N": there
// beta = pi/2 >= theta_M and the front is the whole period), nor the floor of beta at the
// horizon. Tested by scanning f along longitudes.
#pragma once

#include <string>
#include <vector>

#include "models/classic_models.h"
#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

/// The projection of a direction on the cross-section of the cylinders (the y-z plane): side
/// s = +1 for k_y >= 0, else -1, and elevation beta = atan2(k_z, |k_y|) floored at
/// kGrazingCosFloor (Walker's theta_L = s (pi/2 - beta)).
struct PfProjection {
  int side = 1;
  double beta = 0.0;
};

/// The part of one period a direction lights or sees: the arc psi in [arc_lo, arc_hi] and the
/// floor t in [floor_lo, floor_hi] (t from 0 at the foot of the cylinder on the -y side to w).
struct PfFront {
  double arc_lo = 0.0, arc_hi = 0.0;
  double floor_lo = 0.0, floor_hi = 0.0;
};

/// A crease of k -> f(k, fixed): its longitude about +x, and whether f's first derivative jumps
/// there (kink) or only its second (the integrand vanishes at the moving limit: C1).
struct PfCrease {
  double longitude = 0.0;
  bool kink = true;
};

/// ∫_{t_a}^{t_b} cos^m t dt for -pi/2 <= t_a <= t_b <= pi/2, m >= 0 real, by incomplete beta
/// functions: ∫_0^tau cos^m = B(sin^2 tau; 1/2, (m+1)/2)/2 and ∫_tau^{pi/2} cos^m =
/// B(cos^2 tau; (m+1)/2, 1/2)/2, the difference taken where it does not cancel. 0 on error.
double cos_power_integral(double m, double t_a, double t_b) noexcept;

/// (x - sin x cos x)/2 = ∫_0^x sin^2, accurate for small x (series), odd.
double integral_sin_squared(double x) noexcept;

class PoulinFournier final : public Model {
 public:
  /// kd, ks, n: the local blinn-phong model (kd + ks <= 1 checked by the registry); d: distance
  /// between the axes of neighbouring cylinders (radius 1); h: height of the floor above the axes.
  PoulinFournier(double kd, double ks, double n, double d, double h);

  std::string spec() const override;
  /// Anisotropic; reciprocal (a symmetric expression, measured); plausible (albedo <= kd + ks,
  /// measured).
  Traits traits() const override { return {false, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  /// Creases (see above) about the x axis, and peaks at the mirror directions of `fixed` about
  /// the normals N(psi), psi in {-theta_M, -theta_M/2, 0, theta_M/2, theta_M}, width 2/sqrt(n)
  /// (blinn-phong's): the highlight is a band along the cone j_x = -i_x.
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

  // The geometry, exposed for tests.
  double theta_M() const { return theta_M_; }
  double floor_width() const { return floor_w_; }
  double d() const { return d_; }
  PfProjection project(const Vec3& k) const noexcept;
  PfFront front(const PfProjection& p) const noexcept;
  /// theta_s (theta_h for the eye) of app. D for elevation beta < theta_M, not clamped to
  /// theta_M: where the shadow of the neighbour on the side of k meets the arc (pi/2: it misses).
  double neighbour_limit(double beta) const noexcept;
  /// f_s (f_h) of app. D for elevation beta: floor length shadowed (hidden) by the cylinder on the
  /// side of k.
  double floor_blocked(double beta) const noexcept;
  /// The creases of k -> f(k, fixed) (equally of f(fixed, k)), sorted, longitudes in (-pi/2, pi/2).
  std::vector<PfCrease> creases(const Vec3& fixed) const;
  std::vector<double> crease_longitudes(const Vec3& fixed) const;

  /// The two arc integrals of f before the 1/d: ∫_a^b (N.i)(N.j)/((n.i)(n.j)) dpsi and
  /// ∫_a^b (N.h)^n (N.i)(N.j)/((n.i)(n.j)) dpsi for psi in [a, b] (h the unit halfway vector).
  double arc_cosine_product(const PfProjection& pi, const PfProjection& pj, double a, double b) const noexcept;
  double arc_specular(const PfProjection& pi, const PfProjection& pj, double a, double b, const Vec3& h) const noexcept;

 private:
  double kd_, ks_, n_, d_, h_;
  double theta_M_, floor_w_, C_;
  BlinnPhong local_;  // the local model on the arc and the floor
};

void register_poulin_fournier_models(std::vector<ModelInfo>& catalogue);

}  // namespace ganzfeld
