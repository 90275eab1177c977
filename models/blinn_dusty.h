// Blinn's reflection law for a layer of small particles: J. F. Blinn, "Light Reflection Functions
// for Simulation of Clouds and Dusty Surfaces", SIGGRAPH '82 (Computer Graphics 16(3)), the
// low-albedo (single-scattering) reflection law; Walker 1999 (MSc thesis, U. Oregon), ch. III
// "Blinn", eq. III.30, and appendix D (the phase functions).
//
// Conventions as in models/model.h: local frame n = +z, i towards the source, j towards the eye,
// mu_i = i·n (Blinn's mu_0), mu_j = j·n (Blinn's mu); f in 1/sr.
//
// Blinn's phase angle alpha is the angle between the directions *to the light* and *to the eye*
// seen from a particle, cos alpha = L·E = i·j: alpha = 0 is backscatter (the eye at the source),
// alpha = pi forward scatter. The scattering angle of radiative transfer is pi - alpha.
//
// Phase functions Phi(alpha) are normalized as in Blinn's paper (and Chandrasekhar's):
//   (1/4pi) ∫_sphere Phi dOmega = 1,  i.e.  (1/2) ∫_0^pi Phi(alpha) sin alpha d alpha = 1,
// so Phi = 1 is isotropic scattering and Phi/(4pi) is the probability per steradian.
//
// From Blinn's brightness to the BRDF. Blinn's derivation, in optical depth s = n pi rho^2 t
// (n particles of radius rho per unit volume, depth t; tau = n pi rho^2 T for thickness T): the
// particles in ds are lit through exp(-s/mu_0), cover the fraction ds/mu of the view, each looks
// as bright as w Phi(alpha), and their light leaves through exp(-s/mu). Over the layer,
//   B = ∫_0^tau w Phi e^{-s/mu_0} e^{-s/mu} ds/mu
//     = w Phi(alpha) mu_0/(mu + mu_0) [1 - exp(-tau (1/mu + 1/mu_0))].
// In radiometric units: a particle of cross-section pi rho^2 in a beam of flux H_0 (per unit
// area normal to the beam) intercepts H_0 pi rho^2, re-emits the fraction w of it, distributed
// as Phi/(4pi) per steradian; seen as a disk of area pi rho^2 its radiance is H_0 w Phi/(4pi).
// So B = 4pi L_out/H_0 (Blinn's unit is the radiance of an isotropic white particle), and with
// the irradiance E_in = H_0 mu_0 of the surface,
//   f = L_out/E_in = B/(4pi mu_0) = w Phi(alpha) [1 - exp(-tau (1/mu_i + 1/mu_j))]
//                                   / (4pi (mu_i + mu_j)).
// This is Chandrasekhar's single-scattering reflection of a plane-parallel slab (Radiative
// Transfer, 1960, ch. I), which Blinn cites, and Hanrahan & Krueger's (1993) f_r^(1) without
// the Fresnel factors. It is symmetric in (i, j): reciprocal. Its albedo is the fraction of the
// beam scattered once and escaping upwards: of the beam, 1 - exp(-tau/mu_i) is intercepted and w
// of that re-emitted, so a(i) = w ∫_up Phi/(4pi) mu_j/(mu_i + mu_j) [1 - exp(...)] dOmega_j
// <= w (1 - exp(-tau/mu_i)) <= w <= 1: plausible for every parameter value. (Multiple
// scattering, which Blinn's low-albedo law neglects, would add to it.)
#pragma once

#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld {

struct ModelInfo;

/// Blinn's phase functions (Blinn 1982, "phase functions"; Walker app. D), numbered as the
/// `phase` parameter of the spec.
enum class BlinnPhase {
  constant = 0,           ///< Phi = 1 (isotropic; particles small against the wavelength)
  anisotropic = 1,        ///< Phi = 1 + x cos alpha, |x| <= 1 (x > 0 favours backscatter)
  lambert_sphere = 2,     ///< Phi = 8/(3pi) (sin alpha + (pi - alpha) cos alpha) (large Lambertian spheres)
  rayleigh = 3,           ///< Phi = 3/4 (1 + cos^2 alpha)
  henyey_greenstein = 4,  ///< Phi = (1 - g^2)/(1 + g^2 - 2g cos alpha)^(3/2), g > 0 backscatter
  two_term_hg = 5,        ///< Phi = m HG(g) + (1 - m) HG(g2) (Blinn's Saturn-ring mixture)
};

/// The phase angle alpha between two unit vectors, with 1 - cos alpha = |i - j|^2/2 and
/// 1 + cos alpha = |i + j|^2/2 kept to full relative precision near alpha = 0 and pi, where the
/// sharp Henyey–Greenstein lobes, the zeros of 1 + x cos alpha (x = ±1) and of the Lambert-sphere
/// law (alpha = pi) lie.
struct PhaseAngle {
  double cos = 1.0;
  double one_minus_cos = 0.0, one_plus_cos = 2.0;
  /// Symmetric in (i, j) bit for bit: reciprocity is exact.
  static PhaseAngle between(const Vec3& i, const Vec3& j) noexcept;
  /// From the angle in radians (clamped to [0, pi]).
  static PhaseAngle of(double alpha) noexcept;
};

/// The phase function with its parameters (unused ones are ignored).
struct BlinnPhaseFunction {
  BlinnPhase kind = BlinnPhase::constant;
  double x = 0.0;   ///< anisotropy of `anisotropic`, in [-1, 1]
  double g = 0.0;   ///< Henyey–Greenstein asymmetry (Blinn's sign: <cos alpha> = g), |g| < 1
  double g2 = 0.0;  ///< second Henyey–Greenstein term of `two_term_hg`
  double m = 1.0;   ///< weight of HG(g) in `two_term_hg`, in [0, 1]

  /// Phi(alpha), normalized: (1/2) ∫_0^pi Phi sin alpha d alpha = 1. Never negative.
  double operator()(const PhaseAngle& a) const noexcept;
};

/// Henyey & Greenstein 1941 in Blinn's form, (1 - g^2)/(1 + g^2 - 2g cos alpha)^(3/2):
/// with the phase angle alpha, g > 0 scatters back towards the source (<cos alpha> = g); the
/// radiative-transfer asymmetry parameter <cos(scattering angle)> is -g. 0 for |g| >= 1.
double henyey_greenstein(double g, const PhaseAngle& a) noexcept;

/// Blinn 1982, low-albedo reflection from a layer of optical thickness tau (models/blinn_dusty.h
/// header comment):
///   f = w Phi(alpha) [1 - exp(-tau (1/mu_i + 1/mu_j))] / (4pi (mu_i + mu_j)),  cos alpha = i·j.
/// Horizon: 1 - exp(...) -> 1 as either cosine -> 0, so f keeps its finite limit
/// w Phi/(4pi mu_other); when both graze, mu_i + mu_j is floored at kGrazingCosFloor (as Hapke's
/// 1/(mu_i + mu_j) in models/classic.cpp).
class BlinnDusty final : public Model {
 public:
  BlinnDusty(double w, double tau, BlinnPhaseFunction phase);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  const BlinnPhaseFunction& phase() const { return phase_; }

 private:
  double w_, tau_;
  BlinnPhaseFunction phase_;
};

/// Registers `blinn-dusty` (models/registry.h).
void register_blinn_dusty_models(std::vector<ModelInfo>& catalogue);

}  // namespace ganzfeld
