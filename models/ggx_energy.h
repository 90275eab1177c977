// GGX and Charlie albedos by a deterministic rule written apart from integrate/ (and from
// models/ggx's functions): the independent check of the cubature's real-time tables
// (tables/preset.h; tests/preset_test.cpp, the accuracy report), and the E(μ) that ggx-ms
// (models/ggx_ms.h) builds at construction, since models/ cannot call integrate/'s cubature.
//
// The albedo for the viewing direction v (cos θ_v = μ > 0) is an integral over the half vector:
//   a(v) = ∫ f(v, o) cos θ_o dω_o = ∫ f(v, o) cos θ_o 4 (v·h) sin θ_h dθ_h dφ_h   (Walter 2007 eq. 14)
// over o = 2 (v·h) h − v above the horizon. With v = (sin θ_v, 0, μ) and h at (θ_h, φ_h),
//   o_z = sin θ_v cos φ_h sin 2θ_h + μ cos 2θ_h = R cos(2θ_h − δ),  δ = atan2(sin θ_v cos φ_h, μ),
// so o_z > 0 is exactly θ_h < θ*(φ_h) = δ/2 + π/4: the horizon is a known curve, not an
// indicator. The rule: tensor Gauss–Legendre (Boost.Math's 20-point rule, not integrate/'s
// Gauss–Kronrod) over φ_h ∈ [0, π] (the integrand is even in φ_h) in equal panels, and for
// each φ_h over θ_h ∈ [0, θ*] in panels cut geometrically towards the lobe's scale α at both
// θ_h = 0 (GGX's normals) and θ_h = π/2 (Charlie's normals crowd into the surface plane). The
// integrand is smooth on each panel (it vanishes continuously at θ*), so the rule converges
// fast; `error` is |rule(level) − rule(level + 1)| with twice the panels in each direction.
#pragma once

namespace ganzfeld::ggx {

struct ReferenceValue {
  double value = 0.0;
  double error = 0.0;  ///< |this level − the next finer|: the reference's own error estimate
};

/// GGX (Trowbridge–Reitz, Smith Λ) albedo with Schlick F = f0 + (1 − f0)(1 − v·h)⁵ at
/// cos θ_v = mu in [0, 1], alpha in (0, 1]; separable: G1 G1, else height-correlated G2.
ReferenceValue ggx_albedo_reference(double mu, double alpha, double f0, bool separable, int level = 1);
/// One level of that rule, without the error estimate (half the work of the finer level).
double ggx_albedo_rule(double mu, double alpha, double f0, bool separable, int level);

/// Charlie sheen albedo (Estevez–Kulla D, Neubelt–Pettineo visibility) at mu in (0, 1].
ReferenceValue charlie_albedo_reference(double mu, double alpha, int level = 1);

}  // namespace ganzfeld::ggx
