// g and h of every Koenderink–Pont lobe, both halfway-vector-disk models and five classic models
// against a reference that is not ganzfeld's engine (issue #18): Boost.Math's adaptive
// gauss_kronrod<61>, nested, on the lune written out here from its definition, with break points
// at the directions where each lobe peaks. The engine's answer must agree within its own
// error estimate plus the reference's.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "integrate/laws.h"
#include "laws/spec.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;
constexpr double kEngineTol = 1e-8, kReferenceTol = 1e-10;

Vec3 mirror_of(const Vec3& j) { return {-j.x, -j.y, j.z}; }

/// The lune {k·n > 0, k·i > 0} (i = n: the hemisphere) in coordinates about its edge axis e:
/// k = cos t (cos psi n + sin psi b) + sin t e, t in (-pi/2, pi/2), dk = cos t dt dpsi, with
/// k·n = cos t cos psi and k·i = cos t cos(psi - psi_i): psi spans the intersection of the two
/// half-circles.
struct LuneCoordinates {
  Vec3 n{0, 0, 1}, e, b;
  double psi_lo = 0.0, psi_hi = 0.0;
  explicit LuneCoordinates(const Vec3& i) {
    const Vec3 axis = glm::cross(n, i);
    e = glm::length(axis) > 1e-12 ? glm::normalize(axis) : Vec3{1, 0, 0};
    b = glm::cross(e, n);
    const double psi_i = std::atan2(glm::dot(i, b), glm::dot(i, n));
    psi_lo = std::max(-pi / 2, psi_i - pi / 2);
    psi_hi = std::min(pi / 2, psi_i + pi / 2);
  }
  Vec3 direction(double t, double psi) const { return std::cos(t) * (std::cos(psi) * n + std::sin(psi) * b) + std::sin(t) * e; }
  /// (t, psi) of a direction, for break points.
  std::pair<double, double> coordinates(const Vec3& k) const {
    return {std::asin(std::clamp(glm::dot(k, e), -1.0, 1.0)), std::atan2(glm::dot(k, b), glm::dot(k, n))};
  }
};

/// Panels of [lo, hi] cut at each break point strictly inside, widened by a few lobe widths.
std::vector<double> cuts(double lo, double hi, const std::vector<double>& centres) {
  std::vector<double> out{lo, hi};
  for (double c : centres)
    for (double w : {-0.2, -0.05, 0.0, 0.05, 0.2})
      if (c + w > lo && c + w < hi) out.push_back(c + w);
  std::sort(out.begin(), out.end());
  // Merge cuts closer than 1e-9 (a peak on the edge axis lands at t = 1e-17, not 0): a sliver
  // panel makes the relative-error rule recurse on rounding noise.
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return b - a < 1e-9; }), out.end());
  return out;
}

struct Reference {
  double value = 0.0, error = 0.0;
};

/// ∫_lune (k·n) f(k, j) dk by nested Boost GK61 over the cut panels.
Reference lune_integral(const Model& model, const Vec3& i, const Vec3& j) {
  using boost::math::quadrature::gauss_kronrod;
  const LuneCoordinates lune(i);
  std::vector<double> t_centres, psi_centres;
  for (const Vec3& peak : {mirror_of(j), j}) {
    const auto [t, psi] = lune.coordinates(peak);
    t_centres.push_back(t);
    psi_centres.push_back(psi);
  }
  const std::vector<double> tc = cuts(-pi / 2, pi / 2, t_centres), pc = cuts(lune.psi_lo, lune.psi_hi, psi_centres);
  Reference out;
  auto inner = [&](double t) {
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < pc.size(); ++k)
      sum += gauss_kronrod<double, 61>::integrate(
          [&](double psi) {
            const Vec3 d = lune.direction(t, psi);
            return std::cos(t) * std::max(d.z, 0.0) * model.f(d, j);
          },
          pc[k], pc[k + 1], 10, kReferenceTol);
    return sum;
  };
  for (std::size_t k = 0; k + 1 < tc.size(); ++k) {
    double error = 0.0;
    out.value += gauss_kronrod<double, 61>::integrate(inner, tc[k], tc[k + 1], 10, kReferenceTol, &error);
    out.error += error;
  }
  return out;
}

const std::vector<std::string>& models() {
  static const std::vector<std::string> specs{
      "lambert", "minnaert:xi=0.3", "minnaert:xi=2", "specular:alpha=8", "specular:alpha=100", "backscatter:alpha=8",
      "perfect-backscatter:alpha=3", "asperity:alpha=4", "hvd-empirical:cd=0.5,f0=0.3,k=0.3,ns=20,nr=10",
      "hvd-fit:cd=0.5,f0=0.05,f90=1,k=0.4,n1=20,r1=0.3,n2=10,r2=0.4", "phong-lewis", "blinn-phong", "cook-torrance",
      "oren-nayar", "ward", "ggx:alpha=0.3"};
  return specs;
}

/// Cases where the engine's estimate is below its actual error against this reference, found by
/// this test and confirmed by the engine itself at 1e-12 (0.284666909227624 ± 9.9e-13 vs the
/// reference's 0.284666909226393 ± 2.2e-12). Listed, not hidden: the test fails if the list
/// changes either way (a new dishonest case, or this one fixed), and docs/architecture.md
/// names it. The engine's raw |K - G| estimate undershoots here by 30%.
const std::set<std::string> kKnownDishonest{"cook-torrance g at theta_i 35, theta_j 70, phi 0"};

/// Records `what` in `dishonest` when the engine's answer is further from the reference than
/// the engine's own estimate plus the reference's; a non-converged answer fails outright.
void check_agreement(const std::string& what, const Estimate& engine, const Reference& reference,
                     std::set<std::string>& dishonest) {
  EXPECT_TRUE(engine.converged) << what;
  if (std::abs(engine.value - reference.value) <= engine.error + reference.error + 1e-13) return;
  dishonest.insert(what);
  std::printf("dishonest: %s: engine %.17g ± %.3g, reference %.17g ± %.3g\n", what.c_str(), engine.value, engine.error,
              reference.value, reference.error);
}

std::string degrees(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// The engine's g or h of every model at the given geometries (theta_i, theta_j, phi in degrees;
/// for h theta_i is unused) against the reference; returns the dishonest cases.
std::set<std::string> dishonest_cases(Law law, const std::vector<std::array<double, 3>>& geometries) {
  CubatureOptions options;
  options.abs_tol = kEngineTol;
  std::set<std::string> dishonest;
  for (const std::string& spec : models()) {
    const ModelPtr model = parse_model(spec);
    for (const auto& [theta_i, theta_j, phi] : geometries) {
      const Vec3 j = direction(theta_j * pi / 180, phi * pi / 180);
      if (law == Law::g) {
        const Vec3 i = direction(theta_i * pi / 180, 0.0);
        check_agreement(spec + " g at theta_i " + degrees(theta_i) + ", theta_j " + degrees(theta_j) + ", phi " +
                            degrees(phi),
                        vignetting(*model, i, j, options), lune_integral(*model, i, j), dishonest);
      } else {
        check_agreement(spec + " h at theta_j " + degrees(theta_j), darkening(*model, j, options),
                        lune_integral(*model, Vec3{0, 0, 1}, j), dishonest);
      }
    }
  }
  return dishonest;
}

TEST(IndependentReference, VignettingOfEveryLobeFamily) {
  std::vector<std::array<double, 3>> geometries;
  for (double theta_i : {35.0, 120.0})
    for (double theta_j : {20.0, 70.0})
      for (double phi : {0.0, 180.0}) geometries.push_back({theta_i, theta_j, phi});
  EXPECT_EQ(dishonest_cases(Law::g, geometries), kKnownDishonest);
}

TEST(IndependentReference, DarkeningOfEveryLobeFamily) {
  const double azimuth = 0.5 * 180 / pi;  // radians 0.5: off every plane of symmetry
  EXPECT_TRUE(dishonest_cases(Law::h, {{0, 0, azimuth}, {0, 45, azimuth}, {0, 80, azimuth}}).empty());
}

}  // namespace
}  // namespace ganzfeld
