#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

PerfectBackscatter::PerfectBackscatter(int alpha)
    : alpha_(alpha), C_pb_times_2_pow_alpha_((1.0 + alpha) / (2.0 * pi)) {}

std::string PerfectBackscatter::spec() const {
  return spec_text({"perfect-backscatter", {{"alpha", static_cast<double>(alpha_)}}});
}

double PerfectBackscatter::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double denominator = i.z + j.z;
  // Both on the horizon: f ~ 1/((i+j)·n) is unbounded on this null set; (k·n) f stays
  // bounded in every law, and we return 0 there rather than Inf.
  if (denominator <= 0.0) return 0.0;
  const double x = std::clamp(0.5 * (1.0 + glm::dot(i, j)), 0.0, 1.0);
  return C_pb_times_2_pow_alpha_ * std::pow(x, alpha_) / denominator;
}

std::optional<GlslF> PerfectBackscatter::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float denominator = i.z + j.z;\n"
                   "  if (denominator <= 0.0) return 0.0;\n"
                   "  return " +
                   decimal_literal(C_pb_times_2_pow_alpha_) + " * gz_half_cos_power(i, j, " + decimal_literal(alpha_) +
                   ") / denominator;\n",
               {"gz_half_cos_power"}};
}

MassHints PerfectBackscatter::mass_hints(const Vec3& fixed, Varying) const {
  // The lobe on `fixed`, and (k·n)/((k + fixed)·n) switching from 0 to 1 over k·n ~ fixed·n.
  return HintBuilder().lobe(fixed, std::sqrt(2.0 / alpha_)).layer(fixed.z).build();
}

namespace perfect_backscatter {
double C_pb_printed(double alpha) { return (1.0 + alpha) / (std::pow(2.0, 1.0 + alpha) * pi); }
// (i·n) f(i,i) = C_pb 2^alpha (i·n) / (2 i·n).
double retro_radiance(double alpha) { return (1.0 + alpha) / (4.0 * pi); }
}  // namespace perfect_backscatter
}  // namespace ganzfeld
