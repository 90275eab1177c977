#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

Backscatter::Backscatter(double alpha) : alpha_(alpha), C_b_(backscatter::C_b(alpha)) {}

std::string Backscatter::spec() const { return spec_text({"backscatter", {{"alpha", alpha_}}}); }

double Backscatter::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double x = std::clamp(0.5 * (1.0 + glm::dot(i, j)), 0.0, 1.0);
  return C_b_ * std::pow(x, alpha_);
}

std::optional<GlslF> Backscatter::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(C_b_) + " * gz_half_cos_power(i, j, " +
                   decimal_literal(alpha_) + ");\n",
               {"gz_half_cos_power"}};
}

MassHints Backscatter::mass_hints(const Vec3& fixed, Varying) const {
  return HintBuilder().lobe(fixed, std::sqrt(2.0 / alpha_)).build();
}

namespace backscatter {

double C_b_printed(double alpha) { return 6.0 / (5.0 * pi * std::pow(2.0, alpha)); }

// At i = n the backscatter lobe coincides with the specular one, so the largest admissible
// constant is the same (docs/errata.md, backscatter.norm).
double C_b(double alpha) { return cosine_power_lobe_normalization(alpha); }

namespace {
// K&P's angles for alpha = 1: i·n = cos theta, j·n = sin eta sin zeta, [i,j,n] = i·(j×n) =
// -cos zeta sin theta. With i = (sin theta, 0, cos theta), [i,j,n] = sin theta j_y, so
// cos zeta = -j_y (zeta is measured from the lune's edge axis) and eta is j's longitude about
// that axis, measured from the tangent towards n: j = (sin zeta cos eta, -cos zeta,
// sin zeta sin eta).
struct KpAngles {
  double theta, eta, sin_zeta;
};
KpAngles kp_angles(const Vec3& i, const Vec3& j) {
  return {std::atan2(std::hypot(i.x, i.y), i.z), std::atan2(j.z, j.x),
          std::hypot(j.x, j.z)};  // sin zeta without the cancellation of sqrt(1 - j_y^2)
}
}  // namespace

// K&P, g_b for alpha = 1 (printed):
//   3/10 (1 + cos theta) + 1/(5 pi) (cos eta - cos(eta + 2 theta) + 2 (pi - theta) sin eta sin zeta)
double g_alpha1_printed(const Vec3& i, const Vec3& j) {
  const auto [theta, eta, sin_zeta] = kp_angles(i, j);
  return 0.3 * (1.0 + std::cos(theta)) +
         (std::cos(eta) - std::cos(eta + 2 * theta) + 2 * (pi - theta) * std::sin(eta) * sin_zeta) / (5.0 * pi);
}

// Corrected (docs/errata.md): the first bracket term also carries the factor sin zeta.
double g_alpha1(const Vec3& i, const Vec3& j) {
  const auto [theta, eta, sin_zeta] = kp_angles(i, j);
  return 0.3 * (1.0 + std::cos(theta)) +
         sin_zeta * (std::cos(eta) - std::cos(eta + 2 * theta) + 2 * (pi - theta) * std::sin(eta)) / (5.0 * pi);
}

double h_alpha1_printed(double mu_j) { return (3.0 + 2.0 * mu_j) / 5.0; }

}  // namespace backscatter
}  // namespace ganzfeld
