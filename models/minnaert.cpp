#include <cmath>
#include <numbers>

#include <boost/math/special_functions/beta.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/special_functions/hypergeometric_pFq.hpp>

#include "models/kp_lobes.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

Minnaert::Minnaert(double xi) : xi_(xi), C_d_(minnaert::C_d(xi)) {}

std::string Minnaert::spec() const { return spec_text({"minnaert", {{"xi", xi_}}}); }

double Minnaert::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double x = i.z * j.z;
  return C_d_ * (xi_ == 1.0 ? x : std::pow(x, xi_));  // pow(x, 1) is x: glibc's pow is within 0.52 ulp
}

std::optional<GlslF> Minnaert::glsl_f() const {
  if (xi_ == 0.0) return GlslF{std::string(kGlslBelowHorizon) + "  return " + decimal_literal(C_d_) + ";\n", {}};
  // 1 - (i.n)(j.n) = (|i_xy|^2 + |j_xy|^2 + (i.z - j.z)^2)/2 for unit i, j: accurate near the normal.
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float u = 0.5 * (dot(i.xy, i.xy) + dot(j.xy, j.xy) + (i.z - j.z) * (i.z - j.z));\n"
                   "  return " +
                   decimal_literal(C_d_) + " * gz_pow_pair(i.z * j.z, u, " + decimal_literal(xi_) + ");\n",
               {"gz_pow_pair"}};
}

MassHints Minnaert::mass_hints(const Vec3&, Varying) const {
  // The integrand (k·n)^(xi+1) ~ exp(-(xi+2) theta^2 / 2): a lobe on n of width 1/sqrt(xi+2).
  const double width = 1.0 / std::sqrt(xi_ + 2.0);
  HintBuilder hints;
  if (width <= 0.3) hints.lobe(Vec3{0, 0, 1}, width);
  return hints.rough_horizon(xi_ < 1.0 && xi_ > 0.0).build();
}

namespace minnaert {

// K&P: "The value of the constant C_d has been chosen to be the maximum value that does not
// violate energy conservation": a_d(i) = (i·n)^xi <= 1.
double C_d(double xi) { return (2.0 + xi) / (2.0 * pi); }

// K&P, g_d for xi = 1 (printed).
double g_xi1_printed(double c, double mu_j) { return mu_j / pi * lune_moment_2(c); }

// K&P, g_d "in terms of confluent hypergeometric functions" (printed):
//   Gamma((3+xi)/2) / (sqrt(pi) Gamma(1+xi/2)) (i·n) (j·n)^xi 2F1(1/2, -xi/2; 3/2; (i·n)^2).
// 2F1 at z = 1 by Gauss's theorem (the series converges too slowly there), else Boost's pFq.
double g_hyp2f1_printed(double c, double mu_j, double xi) {
  const double K = boost::math::tgamma_ratio((3.0 + xi) / 2.0, 1.0 + xi / 2.0) / std::sqrt(pi);
  const double z = c * c;
  double F;
  if (z >= 1.0) {
    F = boost::math::tgamma(1.5) * boost::math::tgamma(1.0 + xi / 2.0) /
        (boost::math::tgamma(1.0) * boost::math::tgamma(1.5 + xi / 2.0));
  } else {
    F = boost::math::hypergeometric_pFq({0.5, -xi / 2.0}, {1.5}, z);
  }
  return K * c * std::pow(mu_j, xi) * F;
}

// K&P, g_d with the incomplete beta function B_z(a, b) = ∫_0^z t^(a-1) (1-t)^(b-1) dt (printed):
//   Gamma((3+xi)/2) / (xi sqrt(pi) Gamma(xi/2)) (j·n)^xi B_{(i·n)^2}(1/2, 1 + xi/2).
// xi Gamma(xi/2) = 2 Gamma(1 + xi/2) keeps xi -> 0 finite.
double g_betainc_printed(double c, double mu_j, double xi) {
  const double K = boost::math::tgamma_ratio((3.0 + xi) / 2.0, 1.0 + xi / 2.0) / (2.0 * std::sqrt(pi));
  return K * std::pow(mu_j, xi) * boost::math::beta(0.5, 1.0 + xi / 2.0, c * c);
}

// Corrected g_d (docs/errata.md): the lune integral is half the hemisphere at c = 0 plus an odd
// part, (j·n)^xi [1/2 + K ∫_0^c (1 - t^2)^(xi/2) dt], with K = Gamma((3+xi)/2)/(sqrt(pi)
// Gamma(1+xi/2)) and ∫_0^c (1-t^2)^(xi/2) dt = sign(c) B_{c^2}(1/2, 1+xi/2) / 2 (DLMF 8.17.8).
double g(double c, double mu_j, double xi) {
  const double K = boost::math::tgamma_ratio((3.0 + xi) / 2.0, 1.0 + xi / 2.0) / std::sqrt(pi);
  const double odd = std::copysign(0.5 * boost::math::beta(0.5, 1.0 + xi / 2.0, c * c), c);
  return std::pow(mu_j, xi) * (0.5 + K * odd);
}

double h(double mu_j, double xi) { return std::pow(mu_j, xi); }
double a(double mu_i, double xi) { return std::pow(mu_i, xi); }
double r(double xi) { return 2.0 / (2.0 + xi); }

}  // namespace minnaert
}  // namespace ganzfeld
