#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"

namespace ganzfeld {

// Defaults of the Model interface live here, with the simplest model.
const char* to_string(EnergyClass c) {
  switch (c) {
    case EnergyClass::conserving: return "conserving";
    case EnergyClass::plausible: return "plausible";
    case EnergyClass::not_plausible: return "not plausible";
  }
  return "?";
}

double Lambert::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return std::numbers::inv_pi;
}

std::optional<GlslF> Lambert::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  return " + glsl_float(std::numbers::inv_pi) + ";\n", {}};
}

double lambert::g(double c) { return 0.5 * (1.0 + c); }

double lune_moment_2(double c) { return std::numbers::pi - std::acos(c) + c * std::sqrt(1.0 - c * c); }

}  // namespace ganzfeld
