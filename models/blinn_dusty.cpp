// Blinn 1982, clouds and dusty surfaces: the low-albedo reflection law and its phase functions.
// Formula, units and conventions: models/blinn_dusty.h; differences from Walker's summary:
// docs/models.md, "blinn-dusty".
#include "models/blinn_dusty.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <utility>

#include "models/classic_models.h"  // kGrazingCosFloor
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

/// sin alpha + (pi - alpha) cos alpha = sin d - d cos d with d = pi - alpha. Near alpha = pi the
/// two terms cancel to d^3/3: there its Taylor series (to d^9, relative error < 1e-14 for
/// d < 0.1) and d = 2 atan2(|i + j|, |i - j|) keep full relative precision.
double lambert_sphere_bracket(const PhaseAngle& a) noexcept {
  const double d = 2.0 * std::atan2(std::sqrt(a.one_plus_cos), std::sqrt(a.one_minus_cos));
  if (d >= 0.1) return std::max(0.0, std::sin(d) - d * std::cos(d));
  const double d2 = d * d;
  return d * d2 * (1.0 / 3.0 - d2 * (1.0 / 30.0 - d2 * (1.0 / 840.0 - d2 / 45360.0)));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
PhaseAngle PhaseAngle::between(const Vec3& i, const Vec3& j) noexcept {
  const Vec3 d = i - j, s = i + j;
  PhaseAngle a;
  a.one_minus_cos = std::clamp(0.5 * glm::dot(d, d), 0.0, 2.0);
  a.one_plus_cos = std::clamp(0.5 * glm::dot(s, s), 0.0, 2.0);
  a.cos = std::clamp(glm::dot(i, j), -1.0, 1.0);
  return a;
}

PhaseAngle PhaseAngle::of(double alpha) noexcept {
  PhaseAngle a;
  alpha = std::clamp(alpha, 0.0, pi);
  const double half_sin = std::sin(0.5 * alpha), half_cos = std::cos(0.5 * alpha);
  a.cos = std::cos(alpha);
  a.one_minus_cos = 2.0 * half_sin * half_sin;
  a.one_plus_cos = 2.0 * half_cos * half_cos;
  return a;
}

double henyey_greenstein(double g, const PhaseAngle& a) noexcept {
  // (1/2) ∫_{-1}^{1} (1 - g^2)(1 + g^2 - 2g c)^{-3/2} dc = 1 for |g| < 1; |g| = 1 is a delta
  // (0/0 here): outside the model's range, returned as 0. The denominator written about the
  // peak, (1 - g)^2 + 2g (1 - c) for g >= 0 and (1 + g)^2 - 2g (1 + c) for g < 0, keeps its
  // relative precision where it is smallest (~(1 - |g|)^2 = 1e-4 at |g| = 0.99).
  if (!(std::abs(g) < 1.0)) return 0.0;
  const double d =
      g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * a.one_minus_cos : (1.0 + g) * (1.0 + g) - 2.0 * g * a.one_plus_cos;
  return (1.0 - g * g) / (d * std::sqrt(d));
}

double BlinnPhaseFunction::operator()(const PhaseAngle& a) const noexcept {
  switch (kind) {
    case BlinnPhase::constant: return 1.0;
    case BlinnPhase::anisotropic:
      // Blinn's 1 + x cos alpha (its mean over the sphere is 1), written as (1 - |x|) + |x|(1 ± c)
      // so that its zero at x = ±1 is approached with full relative precision.
      return x >= 0.0 ? (1.0 - x) + x * a.one_plus_cos : (1.0 + x) - x * a.one_minus_cos;
    case BlinnPhase::lambert_sphere:
      // Phase law of a large Lambertian sphere (Russell 1916; Blinn 1982); 8/(3pi) normalizes it
      // ((1/2) ∫ (sin a + (pi - a) cos a) sin a da = 3pi/8).
      return 8.0 / (3.0 * pi) * lambert_sphere_bracket(a);
    case BlinnPhase::rayleigh: return 0.75 * (1.0 + a.cos * a.cos);
    case BlinnPhase::henyey_greenstein: return henyey_greenstein(g, a);
    case BlinnPhase::two_term_hg:  // Blinn's linear combination (Saturn's rings)
      return m * henyey_greenstein(g, a) + (1.0 - m) * henyey_greenstein(g2, a);
  }
  return 0.0;
}

// ---------------------------------------------------------------------------------------------
BlinnDusty::BlinnDusty(double w, double tau, BlinnPhaseFunction phase) : w_(w), tau_(tau), phase_(phase) {}

std::string BlinnDusty::spec() const {
  return spec_text({"blinn-dusty",
                    {{"w", w_},
                     {"tau", tau_},
                     {"phase", static_cast<double>(phase_.kind)},
                     {"x", phase_.x},
                     {"g", phase_.g},
                     {"g2", phase_.g2},
                     {"m", phase_.m}}});
}

double BlinnDusty::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  if (!(tau_ > 0.0)) return 0.0;  // no particles: nothing scatters (also avoids 0 * inf below)
  const double mu_i = std::min(i.z, 1.0), mu_j = std::min(j.z, 1.0);
  const double sum = mu_i + mu_j, prod = mu_i * mu_j;
  // 1 - exp(-tau (1/mu_i + 1/mu_j)) = -expm1(-tau sum/prod): accurate for thin layers (~ tau
  // sum/prod), and 1 in the limit where a cosine vanishes (prod = 0, or sum/prod = inf).
  const double scattered = prod > 0.0 ? -std::expm1(-tau_ * (sum / prod)) : 1.0;
  // Both cosines vanish only on the horizon, where the printed 1/(mu_i + mu_j) diverges:
  // floored at kGrazingCosFloor (models/classic_models.h), a layer of 1e-6 at the horizon.
  return w_ * phase_(PhaseAngle::between(i, j)) * scattered / (4.0 * pi * std::max(sum, kGrazingCosFloor));
}

namespace {
/// Henyey–Greenstein as henyey_greenstein(), its denominator written about the peak.
std::string glsl_henyey_greenstein(double g) {
  const std::string d =
      g >= 0.0 ? decimal_literal((1.0 - g) * (1.0 - g)) + " + " + decimal_literal(2.0 * g) + " * one_minus_cos"
               : decimal_literal((1.0 + g) * (1.0 + g)) + " - " + decimal_literal(2.0 * g) + " * one_plus_cos";
  std::string out = decimal_literal(1.0 - g * g);
  out += " / ((" + d + ") * sqrt(" + d + "))";
  return "(" + out + ")";
}
}  // namespace

std::optional<GlslF> BlinnDusty::glsl_f() const {
  if (!(tau_ > 0.0)) return GlslF{"  return 0.0;\n", {}};
  std::string Phi;
  switch (phase_.kind) {
    case BlinnPhase::constant: Phi = "1.0"; break;
    case BlinnPhase::anisotropic:
      Phi = phase_.x >= 0.0 ? decimal_literal(1.0 - phase_.x) + " + " + decimal_literal(phase_.x) + " * one_plus_cos"
                            : decimal_literal(1.0 + phase_.x) + " - " + decimal_literal(phase_.x) + " * one_minus_cos";
      break;
    case BlinnPhase::lambert_sphere: Phi = decimal_literal(8.0 / (3.0 * pi)) + " * bracket"; break;
    case BlinnPhase::rayleigh: Phi = "0.75 * (1.0 + cos_a * cos_a)"; break;
    case BlinnPhase::henyey_greenstein: Phi = glsl_henyey_greenstein(phase_.g); break;
    case BlinnPhase::two_term_hg:
      Phi = decimal_literal(phase_.m) + " * " + glsl_henyey_greenstein(phase_.g) + " + " +
            decimal_literal(1.0 - phase_.m) + " * " + glsl_henyey_greenstein(phase_.g2);
      break;
  }
  const std::string bracket =
      phase_.kind != BlinnPhase::lambert_sphere ? "" : "  float bracket = gz_lambert_sphere_bracket(i, j);\n";
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float mu_i = min(i.z, 1.0), mu_j = min(j.z, 1.0);\n"
                   "  float sum = mu_i + mu_j, prod = mu_i * mu_j;\n"
                   "  float scattered = prod > 0.0 ? -gz_expm1(-" +
                   decimal_literal(tau_) +
                   " * (sum / prod)) : 1.0;\n"
                   "  vec3 d = i - j, s = i + j;\n"
                   "  float one_minus_cos = clamp(0.5 * dot(d, d), 0.0, 2.0), one_plus_cos = clamp(0.5 * dot(s, s), "
                   "0.0, 2.0);\n"
                   "  float cos_a = clamp(dot(i, j), -1.0, 1.0);\n" +
                   bracket + "  return " + decimal_literal(w_ / (4.0 * pi)) + " * (" + Phi +
                   ") * scattered / max(sum, " + decimal_literal(kGrazingCosFloor) + ");\n",
               {"gz_expm1", "gz_lambert_sphere_bracket"}};
}

MassHints BlinnDusty::mass_hints(const Vec3& fixed, Varying) const {
  // f is symmetric in (i, j), so both integrals see the same features about `fixed`:
  // - a Henyey–Greenstein lobe about cos alpha = sign(g): the source direction for g > 0 (Blinn's
  //   backscatter), its antipode (below the horizon: mass along the forward horizon) for g < 0.
  //   Phi ∝ ((1 - g)^2 + g alpha^2)^{-3/2} near the peak: half maximum at alpha = 0.77 (1 - g)/sqrt(g);
  //   the scale (1 - |g|)/sqrt(|g|) is given (broad for small |g|, which the engine ignores);
  // - the Lommel–Seeliger factor mu/(mu + mu_fixed) switching over mu ~ mu_fixed, and the thin-layer
  //   factor 1 - exp(-tau/mu ...) switching over mu ~ tau: a horizon layer min(mu_fixed, tau), the
  //   floored 1/(mu + mu_fixed) leaving its ramp (kGrazingLayer) when mu_fixed vanishes.
  //   The other phase functions are smooth on the scale of the sphere.
  HintBuilder hints;
  const auto add_hg = [&](double g, double weight) {
    if (!(weight > 0.0) || g == 0.0) return;
    const double ag = std::abs(g);
    hints.lobe(g > 0.0 ? fixed : -fixed, (1.0 - ag) / std::sqrt(ag));
  };
  if (phase_.kind == BlinnPhase::henyey_greenstein) add_hg(phase_.g, 1.0);
  if (phase_.kind == BlinnPhase::two_term_hg) {
    add_hg(phase_.g, phase_.m);
    add_hg(phase_.g2, 1.0 - phase_.m);
  }
  return hints.layer(std::max(fixed.z, kGrazingLayer)).layer(tau_).build();
}

// ---------------------------------------------------------------------------------------------
void register_blinn_dusty_models(std::vector<ModelInfo>& c) {
  c.push_back(
      {"blinn-dusty",
       "Blinn's dusty/cloud layer, single scattering: f = w Phi(a) (1 - exp(-tau (1/i.n + 1/j.n)))/(4 pi (i.n + j.n)), "
       "a = phase angle",
       "Blinn 1982, SIGGRAPH '82 (Computer Graphics 16(3)), low-albedo reflection; Walker 1999, MSc thesis "
       "(U. Oregon), ch. III, Blinn (eq. III.30), app. D",
       {{"w", ParamType::real, 0.0, 1.0, 0.5, "single-scattering albedo of a particle (Blinn's w; thesis rho_d)"},
        {"tau", ParamType::real, 0.0, 1000.0, 1.0,
         "optical thickness of the layer, n pi rho^2 T (>= ~20: semi-infinite, the dusty surface)"},
        {"phase", ParamType::integer, 0.0, 5.0, 0.0,
         "phase function Phi(a), a = angle between i and j (0 = back to the source): 0 constant, 1 anisotropic "
         "1 + x cos a, 2 Lambertian sphere, 3 Rayleigh, 4 Henyey-Greenstein(g), 5 m HG(g) + (1-m) HG(g2)"},
        {"x", ParamType::real, -1.0, 1.0, 0.5, "anisotropy of phase 1 (x > 0 favours backscatter)"},
        {"g", ParamType::real, -0.99, 0.99, 0.5,
         "Henyey-Greenstein parameter of phases 4, 5 in Blinn's sign: g > 0 backscatter, g < 0 forward"},
        {"g2", ParamType::real, -0.99, 0.99, -0.5, "second Henyey-Greenstein parameter (phase 5)"},
        {"m", ParamType::real, 0.0, 1.0, 0.596, "weight of HG(g) in phase 5 (HG(g2) gets 1 - m)"}},
       {true, true, EnergyClass::plausible},
       {},
       [](const ParamValues& p) -> ModelPtr {
         BlinnPhaseFunction phase;
         phase.kind = static_cast<BlinnPhase>(static_cast<int>(p.at("phase")));
         phase.x = p.at("x");
         phase.g = p.at("g");
         phase.g2 = p.at("g2");
         phase.m = p.at("m");
         return std::make_shared<BlinnDusty>(p.at("w"), p.at("tau"), phase);
       }});
}

}  // namespace ganzfeld
