#include <array>
#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"
#include "util/names.h"

namespace ganzfeld {

// Defaults of the Model interface live here, with the simplest model.
const char* to_string(EnergyClass c) {
  constexpr std::array kNames{util::EnumName<EnergyClass>{EnergyClass::conserving, "conserving"},
                              util::EnumName<EnergyClass>{EnergyClass::plausible, "plausible"},
                              util::EnumName<EnergyClass>{EnergyClass::not_plausible, "not plausible"}};
  return util::name_of(kNames, c);
}

double Lambert::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return std::numbers::inv_pi;
}

std::optional<GlslF> Lambert::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(std::numbers::inv_pi) + ";\n", {}};
}

double lambert::g(double c) { return 0.5 * (1.0 + c); }

double lune_moment_2(double c) { return std::numbers::pi - std::acos(c) + c * std::sqrt(1.0 - c * c); }

}  // namespace ganzfeld
