#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/kp_lobes.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

Asperity::Asperity(double alpha) : alpha_(alpha) {}

std::string Asperity::spec() const { return spec_text({"asperity", {{"alpha", alpha_}}}); }

double Asperity::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return std::numbers::inv_pi * std::pow(1.0 - i.z * j.z, alpha_);
}

std::optional<GlslF> Asperity::glsl_f() const {
  // 1 - (i.n)(j.n) = (|i_xy|^2 + |j_xy|^2 + (i.z - j.z)^2)/2 for unit i, j: no cancellation when
  // both stand near the normal.
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float u = 0.5 * (dot(i.xy, i.xy) + dot(j.xy, j.xy) + (i.z - j.z) * (i.z - j.z));\n"
                   "  return " +
                   decimal_literal(std::numbers::inv_pi) + " * gz_pow_pair(u, i.z * j.z, " + decimal_literal(alpha_) +
                   ");\n",
               {"gz_pow_pair"}};
}

MassHints Asperity::mass_hints(const Vec3& fixed, Varying) const {
  // (k·n)(1 - (k·n)(fixed·n))^alpha peaks at k·n = 1/((alpha+1) fixed·n): a layer on the horizon.
  return HintBuilder().layer(1.0 / ((alpha_ + 1.0) * std::max(fixed.z, 1e-300))).build();
}

namespace asperity {

double C_a_printed() { return 1.0 / pi; }

// K&P, g_a "for the realistic value alpha = 1" (printed).
double g_alpha1_printed(double c, double mu_j) {
  return 0.5 * (1.0 + c) - 4.0 * mu_j / (3.0 * pi) * lune_moment_2(c) -
         0.125 * mu_j * mu_j * (c - 2.0) * (c + 1.0) * (c + 1.0);
}

// Corrected (docs/errata.md): g_a = (1/pi)[∫_lune (k·n) dk - (j·n) ∫_lune (k·n)^2 dk]
//                                 = (1 + c)/2 - 2 (j·n)/(3 pi) (pi - arccos c + c sqrt(1 - c^2)).
double g_alpha1(double c, double mu_j) { return 0.5 * (1.0 + c) - 2.0 * mu_j / (3.0 * pi) * lune_moment_2(c); }

double h_alpha1_printed(double mu_j) { return 1.0 - 2.0 * mu_j / 3.0; }

}  // namespace asperity
}  // namespace ganzfeld
