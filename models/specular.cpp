#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

double cosine_power_lobe_normalization(double alpha) {
  return (1.0 + alpha) * (2.0 + alpha) / (2.0 * pi * (2.0 * alpha + std::exp2(-alpha)));
}

Specular::Specular(double alpha) : alpha_(alpha), C_s_(cosine_power_lobe_normalization(alpha)) {}

std::string Specular::spec() const { return spec_text({"specular", {{"alpha", alpha_}}}); }

double Specular::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  // (1 + k·j)/2 with k the mirror of i; clamped against rounding just outside [0, 1].
  const double x = std::clamp(0.5 * (1.0 + glm::dot(mirror(i), j)), 0.0, 1.0);
  return C_s_ * std::pow(x, alpha_);
}

std::optional<GlslF> Specular::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(C_s_) +
                   " * gz_half_cos_power(vec3(-i.x, -i.y, i.z), j, " + decimal_literal(alpha_) + ");\n",
               {"gz_half_cos_power"}};
}

MassHints Specular::mass_hints(const Vec3& fixed, Varying) const {
  // ((1 + cos gamma)/2)^alpha = cos^(2 alpha)(gamma/2) ~ exp(-alpha gamma^2 / 4).
  return HintBuilder().lobe(mirror(fixed), std::sqrt(2.0 / alpha_)).build();
}

namespace specular {

double C_s_printed(double alpha) {
  return (1.0 + alpha) * (2.0 + alpha) / (2.0 * pi * (2.0 * alpha + std::pow(2.0, -alpha)));
}

// K&P: "the albedo is a_s = (3 + 2 i·n)/5 for alpha = 1".
double a_alpha1_printed(double mu_i) { return (3.0 + 2.0 * mu_i) / 5.0; }

// K&P: a_s for alpha = 8 with theta = arccos(i·n) (printed).
double a_alpha8_printed(double mu_i) {
  const double t = std::acos(std::clamp(mu_i, -1.0, 1.0));
  return (24201945.0 + 33554432.0 * std::cos(t) + 9773400.0 * std::cos(2 * t) - 415212.0 * std::cos(4 * t) +
          10728.0 * std::cos(6 * t) - 45.0 * std::cos(8 * t)) /
         67125248.0;
}

}  // namespace specular
}  // namespace ganzfeld
