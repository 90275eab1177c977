// Poulin-Fournier additive cylinders (models/poulin_fournier.h): the closed-form arc integrals
// against quadrature, the thesis's shadowing pseudo-code against 2-D ray casting, the projected
// lengths of eq. III.19 tiling the period, the plane limits (d = 0, h = 1, d -> infinity), known
// values at normal incidence and view, the mirror symmetries, reciprocity measured, finiteness on
// a dense grid including grazing, the creases (scanning f along longitudes about the tangent),
// the mass hints, parameter validation, and the albedo by cubature (integrate/laws.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "tests/test_support.h"

#include "integrate/laws.h"
#include "models/classic_models.h"
#include "models/poulin_fournier.h"
#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

// --- tolerances --------------------------------------------------------------------------------
/// Closed forms (incomplete beta, trigonometric antiderivatives) against adaptive 61-point
/// Gauss-Kronrod asked for 1e-13 (depth 12): rounding of a few terms of size <= the integral's scale.
constexpr double kClosedFormRel = 1e-11;
/// 2-D ray casting with kRaySamples midpoint samples per arc and floor: visibility switches cost
/// O(1/kRaySamples) of the integrand's scale each (measured worst: 1.0e-4 relative).
constexpr int kRaySamples = 40000;
constexpr double kRayCastRel = 1e-3;
/// l_v + f_v = d (eq. III.19): rounding, amplified by 1/cos theta_E (elevations >= 0.01 here).
constexpr double kTilingAbs = 1e-11;
/// f is evaluated on a canonical formula symmetric in (i, j); allow a few ulps.
constexpr double kReciprocalRel = 1e-13;
/// Mirror images are computed from bit-identical projections up to the sign of the side.
constexpr double kMirrorRel = 1e-13;
/// Values below this (1/sr) are compared absolutely (far outside the highlight).
constexpr double kValueFloor = 1e-12;

/// A generic set of geometries: a floor, touching half cylinders (theta_M = 90 deg), overlapping
/// cylinders (no floor, junctions), a wide floor, a low floor with deep cylinders, sparse.
struct Geometry {
  double d, h;
};
const std::vector<Geometry> kGeometries{{2.5, 0.2}, {2.0, 0.0}, {1.5, 0.0}, {4.0, 0.5},
                                        {1.0, 0.9}, {2.2, 0.8}, {12.0, 0.3}};

/// A unit direction with polar angle theta from n and azimuth phi from +x (degrees).
Vec3 dir_deg(double theta, double phi) { return direction(theta * pi / 180, phi * pi / 180); }

std::vector<Vec3> test_directions(unsigned seed, int random_count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> dirs;
  for (double c : {0.0, 1e-300, 1e-12, 1e-6, 1e-3, 0.05, 0.3, 0.7, 1.0 - 1e-12, 1.0})
    for (double phi : {0.0, 0.1, 0.5 * pi, 0.8, pi, 1.5 * pi, 2.0}) dirs.push_back(direction_from_cos(c, phi));
  dirs.push_back({1, 0, 0});
  dirs.push_back({-1, 0, 0});
  dirs.push_back({0, 1, 0});
  dirs.push_back({0, -1, 0});
  for (int k = 0; k < random_count; ++k) dirs.push_back(direction_from_cos(u(rng), 2 * pi * u(rng)));
  return dirs;
}

// --- an independent reference: 2-D ray casting in the cross-section --------------------------
/// Is the ray from p along the projected direction v (v_z > 0) blocked by a cylinder (unit
/// circles at (m d, 0))? `own` is the index of the circle p lies on (none: floor point).
bool blocked(double py, double pz, double vy, double vz, double d, int own, bool on_circle) {
  if (on_circle && (vy * (py - own * d) + vz * pz) < 0.0) return true;  // into its own cylinder
  const int reach = static_cast<int>(std::ceil((2.0 / std::max(vz, 1e-3)) / std::max(d, 1e-3))) + 2;
  for (int m = -reach; m <= reach; ++m) {
    if (on_circle && m == own) continue;
    const double cy = py - m * d, cz = pz;  // p - c
    const double b = cy * vy + cz * vz, c = cy * cy + cz * cz - 1.0;
    const double disc = b * b - c;
    if (disc <= 0.0) continue;
    const double t = -b + std::sqrt(disc);  // the far root: any positive root blocks
    if (t > 1e-12) return true;
  }
  return false;
}

/// f by ray casting: (1/d) [sum over arc samples of f_mu (N.i)(N.j)/((n.i)(n.j)) dpsi and over floor
/// samples of f_mu(n) dt], lit and visible tested by rays; f_mu = blinn-phong(kd, ks, n).
double ray_cast_f(double kd, double ks, double n, double d, double h, const Vec3& i, const Vec3& j) {
  const PoulinFournier model(kd, ks, n, d, h);
  const BlinnPhong local(kd, ks, n);
  const double theta_M = model.theta_M(), w = model.floor_width();
  const double ri = std::hypot(i.y, i.z), rj = std::hypot(j.y, j.z);
  const double iy = i.y / ri, iz = i.z / ri, jy = j.y / rj, jz = j.z / rj;
  double sum = 0.0;
  const double dpsi = 2.0 * theta_M / kRaySamples;
  for (int k = 0; k < kRaySamples; ++k) {
    const double psi = -theta_M + (k + 0.5) * dpsi;
    const double py = std::sin(psi), pz = std::cos(psi);
    if (blocked(py, pz, iy, iz, d, 0, true) || blocked(py, pz, jy, jz, d, 0, true)) continue;
    const Vec3 N{0.0, py, pz};
    // local frame of N: f_mu depends on i, j only through N.i, N.j, N.h (blinn-phong)
    const Vec3 t1{1.0, 0.0, 0.0}, t2 = glm::cross(N, t1);
    const Vec3 il{glm::dot(i, t1), glm::dot(i, t2), glm::dot(i, N)},
        jl{glm::dot(j, t1), glm::dot(j, t2), glm::dot(j, N)};
    sum += local.f(il, jl) * glm::dot(N, i) * glm::dot(N, j) / (i.z * j.z) * dpsi;
  }
  if (w > 0.0) {
    const double dt = w / kRaySamples, y0 = -d + std::sqrt(1.0 - h * h);
    for (int k = 0; k < kRaySamples; ++k) {
      const double py = y0 + (k + 0.5) * dt;
      if (blocked(py, h, iy, iz, d, 0, false) || blocked(py, h, jy, jz, d, 0, false)) continue;
      sum += local.f(i, j) * dt;
    }
  }
  return sum / d;
}

TEST(PoulinFournier, ShadowingPseudoCodeMatchesRayCasting) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  int compared = 0;
  for (const Geometry& g : kGeometries) {
    for (int t = 0; t < 12; ++t) {
      // elevations of the projections >= ~0.06 rad so the rays stay short
      const Vec3 i = direction_from_cos(0.06 + 0.94 * u(rng), 2 * pi * u(rng));
      const Vec3 j = direction_from_cos(0.06 + 0.94 * u(rng), 2 * pi * u(rng));
      for (auto [kd, ks, n] : {std::tuple{1.0, 0.0, 1.0}, std::tuple{0.3, 0.7, 30.0}}) {
        const PoulinFournier m(kd, ks, n, g.d, g.h);
        const double ours = m.f(i, j), ref = ray_cast_f(kd, ks, n, g.d, g.h, i, j);
        const double rel = std::abs(ours - ref) / std::max(ref, 1e-3);
        worst = std::max(worst, rel);
        ++compared;
        EXPECT_LE(rel, kRayCastRel) << m.spec() << " i=(" << i.x << "," << i.y << "," << i.z << ") j=(" << j.x << ","
                                    << j.y << "," << j.z << ") ours=" << ours << " ref=" << ref;
      }
    }
  }
  std::printf("ray casting: %d cases, worst relative difference %.3g\n", compared, worst);
}

// --- the closed forms ----------------------------------------------------------------------------
double gk(const std::function<double(double)>& g, double a, double b) {
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, a, b, 12, 1e-13);
}

TEST(PoulinFournier, CosPowerIntegralIsTheIncompleteBetaClosedForm) {
  const std::vector<std::pair<double, double>> intervals{{0.0, 0.3},    {-0.2, 0.1},       {0.1, 1.5},
                                                         {-1.5, -0.01}, {-pi / 2, pi / 2}, {0.0, 1e-9},
                                                         {1.2, 1.5},    {-0.6, 0.7},       {0.4, 0.41}};
  for (double m : {1.0, 2.0, 2.5, 20.0, 137.3, 1000.0, 10002.0})
    for (auto [a, b] : intervals) {
      const double ours = cos_power_integral(m, a, b);
      // split the reference at 0 and at +-4 lobe widths so Gauss-Kronrod sees the peak
      std::vector<double> cuts{a, b};
      for (double c : {0.0, -4 / std::sqrt(m), 4 / std::sqrt(m)})
        if (c > a && c < b) cuts.push_back(c);
      std::sort(cuts.begin(), cuts.end());
      double ref = 0.0;
      for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
        ref += gk([m](double t) { return std::pow(std::cos(t), m); }, cuts[k], cuts[k + 1]);
      const double scale = cos_power_integral(m, -pi / 2, pi / 2);  // the whole lobe
      EXPECT_NEAR(ours, ref, kClosedFormRel * scale) << "m=" << m << " [" << a << ", " << b << "]";
      if (ref > 1e-100) {  // relative accuracy also in the tails
        EXPECT_NEAR(ours / ref, 1.0, 1e-9) << "m=" << m << " [" << a << ", " << b << "]";
      }
    }
  // known values: ∫_{-pi/2}^{pi/2} cos = 2, cos^2 = pi/2, and the empty interval
  EXPECT_NEAR(cos_power_integral(1.0, -pi / 2, pi / 2), 2.0, 1e-14);
  EXPECT_NEAR(cos_power_integral(2.0, -pi / 2, pi / 2), pi / 2, 1e-14);
  EXPECT_EQ(cos_power_integral(3.0, 0.5, 0.5), 0.0);
  EXPECT_EQ(cos_power_integral(3.0, 0.6, 0.5), 0.0);
}

TEST(PoulinFournier, IntegralOfSinSquaredIsAccurateForSmallArguments) {
  for (double x : {1e-100, 1e-8, 1e-4, 0.01, 0.3, 0.49, 0.5, 0.51, 1.0, 2.0, 3.0}) {
    const long double X = x;
    const long double ref = (X - std::sin(X) * std::cos(X)) / 2;        // long double: fine above ~1e-4
    const long double series = X * X * X / 3 - X * X * X * X * X / 15;  // (2x)^3/24 - (2x)^5/480
    const long double expected = x < 1e-3 ? series : ref;
    EXPECT_NEAR(integral_sin_squared(x) / expected, 1.0, 1e-14) << x;
    EXPECT_EQ(integral_sin_squared(-x), -integral_sin_squared(x));
  }
  EXPECT_EQ(integral_sin_squared(0.0), 0.0);
}

TEST(PoulinFournier, ArcIntegralsMatchQuadratureOfTheirIntegrands) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const PoulinFournier m(0.5, 0.5, 40.0, 2.0, 0.0);  // theta_M = pi/2: the widest arcs
  for (int t = 0; t < 200; ++t) {
    const Vec3 i = direction_from_cos(0.02 + 0.98 * u(rng), 2 * pi * u(rng));
    const Vec3 j = direction_from_cos(0.02 + 0.98 * u(rng), 2 * pi * u(rng));
    const PfProjection pi_ = m.project(i), pj = m.project(j);
    const PfFront fi = m.front(pi_), fj = m.front(pj);
    const double a = std::max(fi.arc_lo, fj.arc_lo), b = std::min(fi.arc_hi, fj.arc_hi);
    ASSERT_LT(a, b);  // the tops of the cylinders are always lit and seen
    const Vec3 h = glm::normalize(i + j);
    auto cosines = [&](double psi) {
      const Vec3 N{0.0, std::sin(psi), std::cos(psi)};
      return std::max(0.0, glm::dot(N, i)) * std::max(0.0, glm::dot(N, j)) / (i.z * j.z);
    };
    auto highlight = [&](double psi) {
      const Vec3 N{0.0, std::sin(psi), std::cos(psi)};
      return std::pow(std::max(0.0, glm::dot(N, h)), 40.0) * cosines(psi);
    };
    const double ref_d = gk(cosines, a, b);
    const double theta_H = std::atan2(h.y, h.z);
    double ref_s = 0.0;
    if (theta_H > a && theta_H < b) ref_s = gk(highlight, a, theta_H) + gk(highlight, theta_H, b);
    else ref_s = gk(highlight, a, b);
    EXPECT_NEAR(m.arc_cosine_product(pi_, pj, a, b), ref_d, kClosedFormRel * std::max(ref_d, 1.0));
    EXPECT_NEAR(m.arc_specular(pi_, pj, a, b, h), ref_s, kClosedFormRel * std::max(ref_d, 1.0));
  }
}

// --- eq. III.19: the visible pieces of one period tile it ---------------------------------------
TEST(PoulinFournier, ProjectedLengthsOfThePeriodSumToD) {
  // l_v + f_v with l_v = [sin(theta_h - theta_E) + sin(theta_sh + theta_E)]/cos theta_E
  // (eq. III.19: the visible arc [-theta_sh, theta_h] projected along the eye onto the mean
  // plane) is the period d for every eye direction: the denominator of eq. III.21.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const Geometry& g : kGeometries) {
    const PoulinFournier m(1.0, 0.0, 1.0, g.d, g.h);
    for (int t = 0; t < 300; ++t) {
      const Vec3 j = direction_from_cos(0.01 + 0.99 * u(rng), 2 * pi * u(rng));
      const PfProjection p = m.project(j);
      const PfFront fr = m.front(p);
      const double theta_E = p.side * (pi / 2 - p.beta);
      auto projected = [&](double psi) { return std::sin(psi - theta_E) / std::cos(theta_E); };
      const double l_v = projected(fr.arc_hi) - projected(fr.arc_lo);
      const double f_v = fr.floor_hi - fr.floor_lo;
      EXPECT_NEAR(l_v + f_v, g.d, kTilingAbs / std::cos(theta_E) * g.d)
          << "d=" << g.d << " h=" << g.h << " theta_E=" << theta_E;
    }
  }
}

// --- limits --------------------------------------------------------------------------------------
TEST(PoulinFournier, PlaneLimitsAreTheLocalModel) {
  const auto dirs = test_directions(1, 60);
  for (auto [kd, ks, n] : {std::tuple{0.7, 0.0, 1.0}, std::tuple{0.4, 0.6, 50.0}}) {
    const BlinnPhong plane(kd, ks, n);
    const PoulinFournier d0(kd, ks, n, 0.0, 0.3), h1(kd, ks, n, 3.0, 1.0);
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        EXPECT_EQ(d0.f(i, j), plane.f(i, j));
        EXPECT_EQ(h1.f(i, j), plane.f(i, j));
      }
    if (ks == 0.0) {
      EXPECT_EQ(d0.f(dirs[20], dirs[30]), kd / pi);  // Lambert
    }
  }
  // Continuity into the limits: d -> 0 and h -> 1 approach the plane (arcs of half-width
  // theta_M ~ d/2 resp. sqrt(2(1-h)) with normals within theta_M of n), and d -> infinity too
  // (the cylinders cover 2/d of the period).
  const BlinnPhong plane(0.6, 0.4, 10.0);
  const Vec3 i = dir_deg(40, 20), j = dir_deg(30, 200);
  for (double eps : {1e-2, 1e-4, 1e-6}) {
    EXPECT_NEAR(PoulinFournier(0.6, 0.4, 10.0, eps, 0.0).f(i, j), plane.f(i, j), 10 * eps) << eps;
    EXPECT_NEAR(PoulinFournier(0.6, 0.4, 10.0, 2.5, 1.0 - eps * eps).f(i, j), plane.f(i, j), 10 * eps) << eps;
    EXPECT_NEAR(PoulinFournier(0.6, 0.4, 10.0, 1.0 / eps, 0.0).f(i, j), plane.f(i, j), 10 * eps) << eps;
  }
}

TEST(PoulinFournier, SparseCylindersCastNoShadowOnNeighbours) {
  // 1/cos theta_L < d - 1 (app. D): the neighbour's shadow line passes below the arc; then the
  // arc is lit down to the terminator and the floor carries the whole shadow.
  const PoulinFournier m(1.0, 0.0, 1.0, 5.0, 0.0);
  for (double beta : {0.3, 0.5, 1.0}) {
    ASSERT_GT((m.d() - 1.0) * std::sin(beta), 1.0);
    EXPECT_EQ(m.neighbour_limit(beta), pi / 2);
    const PfFront fr = m.front({1, beta});
    EXPECT_EQ(fr.arc_hi, pi / 2);
    EXPECT_EQ(fr.arc_lo, -beta);
    // the floor shadow: (1 - cos(beta - pi/2))/sin beta = (1 - sin beta)/sin beta
    EXPECT_NEAR(m.floor_width() - fr.floor_hi, (1.0 - std::sin(beta)) / std::sin(beta), 1e-15);
  }
  // ...while a low sun shadows the whole floor and part of the neighbour
  const PfFront low = m.front({1, 0.1});
  EXPECT_EQ(low.floor_hi, 0.0);
  EXPECT_LT(low.arc_hi, pi / 2);
}

// --- known values --------------------------------------------------------------------------------
TEST(PoulinFournier, KnownValuesAtNormalIncidenceAndView) {
  const Vec3 n{0, 0, 1};
  // Lambert: f(n, n) = (kd/pi) (∫_{-theta_M}^{theta_M} cos^2 + w)/d = (kd/pi)(theta_M + sin theta_M cos theta_M + w)/d.
  for (const Geometry& g : kGeometries) {
    const PoulinFournier m(0.8, 0.0, 1.0, g.d, g.h);
    const double tM = m.theta_M(), w = m.floor_width();
    EXPECT_NEAR(m.f(n, n), 0.8 / pi * (tM + std::sin(tM) * std::cos(tM) + w) / g.d, 1e-15) << g.d << " " << g.h;
  }
  // Touching half-cylinders (d = 2, h = 0): (kd/pi)(pi/2)/2 = kd/4.
  EXPECT_NEAR(PoulinFournier(1.0, 0.0, 1.0, 2.0, 0.0).f(n, n), 0.25, 1e-15);
  // With a highlight of exponent 2 on the half-cylinders: h = n, (N.h)^2 cos^2 = cos^4,
  // ∫ cos^4 over [-pi/2, pi/2] = 3 pi/8: f = ks C(2) (3 pi/8)/2.
  EXPECT_NEAR(PoulinFournier(0.0, 1.0, 2.0, 2.0, 0.0).f(n, n), blinn_phong_normalization(2.0) * 3 * pi / 16, 1e-15);
  // Light overhead, eye at 60 deg in the cross-section (j = (0, sin 60, cos 60)), d = 2, h = 0:
  // theta_E = 60 deg, beta = 30 deg; the eye sees psi in [-30 deg, theta_h] with
  // theta_h = 2 asin(sqrt(sin 30)) - 30 deg = 60 deg; (N.i)(N.j)/(n.i n.j) = cos psi cos(psi - 60)/cos 60.
  {
    const PoulinFournier m(1.0, 0.0, 1.0, 2.0, 0.0);
    const Vec3 j{0.0, std::sin(pi / 3), std::cos(pi / 3)};
    const double a = -pi / 6, b = pi / 3;
    // ∫ cos psi cos(psi - c) = [psi cos c/2 + sin(2 psi - c)/4]
    auto F = [](double psi) { return psi * std::cos(pi / 3) / 2 + std::sin(2 * psi - pi / 3) / 4; };
    EXPECT_NEAR(m.f(n, j), (F(b) - F(a)) / std::cos(pi / 3) / pi / 2.0, 1e-15);
    EXPECT_NEAR(m.f(j, n), m.f(n, j), 1e-16);
  }
  // The tangent direction does not matter for the diffuse part: moving j along x at fixed
  // projection changes nothing.
  const PoulinFournier m(0.9, 0.0, 1.0, 2.5, 0.2);
  const Vec3 i = dir_deg(35, 70);
  const Vec3 j1 = glm::normalize(Vec3{0.0, 0.5, 0.7}), j2 = glm::normalize(Vec3{0.9, 0.5, 0.7});
  EXPECT_NEAR(m.f(i, j1), m.f(i, j2), 1e-15);
}

// --- symmetry, reciprocity, finiteness ---------------------------------------------------------
TEST(PoulinFournier, MirrorSymmetriesOfTheCylinderArray) {
  const auto dirs = test_directions(2, 50);
  auto flip_y = [](const Vec3& v) { return Vec3{v.x, -v.y, v.z}; };
  auto flip_x = [](const Vec3& v) { return Vec3{-v.x, v.y, v.z}; };
  for (const Geometry& g : kGeometries) {
    const PoulinFournier m(0.4, 0.6, 25.0, g.d, g.h);
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        if (i.y == 0.0 || j.y == 0.0) continue;  // the side of an exactly tangential projection is +1 by convention
        const double f = m.f(i, j);
        const double scale = std::max(std::abs(f), kValueFloor);
        EXPECT_NEAR(m.f(flip_y(i), flip_y(j)), f, kMirrorRel * scale) << m.spec();
        EXPECT_NEAR(m.f(flip_x(i), flip_x(j)), f, kMirrorRel * scale) << m.spec();
      }
  }
}

TEST(PoulinFournier, ReciprocityMeasured) {
  const auto dirs = test_directions(4, 80);
  double worst = 0.0;
  for (const Geometry& g : kGeometries) {
    const PoulinFournier m(0.3, 0.7, 100.0, g.d, g.h);
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        const double a = m.f(i, j), b = m.f(j, i);
        const double scale = std::max({std::abs(a), std::abs(b), 1e-300});
        worst = std::max(worst, std::abs(a - b) / scale);
      }
  }
  std::printf("poulin-fournier: worst reciprocity asymmetry %.3g\n", worst);
  EXPECT_LE(worst, kReciprocalRel);
}

TEST(PoulinFournier, FiniteNonNegativeEverywhereAndZeroBelowTheHorizon) {
  const auto dirs = test_directions(6, 150);
  const Vec3 below{0.3, 0.4, -0.866}, up{0, 0, 1};
  double largest = 0.0;
  std::vector<Geometry> geometries = kGeometries;
  for (Geometry extreme :
       {Geometry{100.0, 0.0}, Geometry{1e-12, 0.0}, Geometry{2.0, 1.0 - 1e-15}, Geometry{2.0, 1e-15}})
    geometries.push_back(extreme);
  for (Geometry g : geometries)
    for (auto [kd, ks, n] : {std::tuple{1.0, 0.0, 1.0}, std::tuple{0.0, 1.0, 10000.0}, std::tuple{0.5, 0.5, 1.0}}) {
      const PoulinFournier m(kd, ks, n, g.d, g.h);
      for (const Vec3& i : dirs)
        for (const Vec3& j : dirs) {
          const double f = m.f(i, j);
          ASSERT_TRUE(std::isfinite(f)) << m.spec() << " i=(" << i.x << "," << i.y << "," << i.z << ") j=(" << j.x
                                        << "," << j.y << "," << j.z << ")";
          ASSERT_GE(f, 0.0);
          largest = std::max(largest, f);
        }
      EXPECT_EQ(m.f(below, up), 0.0);
      EXPECT_EQ(m.f(up, below), 0.0);
    }
  std::printf("poulin-fournier: largest f on the grid (grazing included) %.4g /sr\n", largest);
}

TEST(PoulinFournier, GrazingLimitOfTheEye) {
  // Eye grazing across the cylinders (theta_E -> 90 deg): only the tops are seen, with normals
  // -> n; light overhead lights them: f -> (local model at n), and the floor of beta at 1e-6
  // keeps f finite on the horizon itself.
  const PoulinFournier m(1.0, 0.0, 1.0, 2.5, 0.2);
  const Vec3 n{0, 0, 1};
  // Measured: f = 1/pi - 0.35 c ... 0.40 c (c = 1e-2 ... 1e-6), linear in c: the tolerance is
  // half of c, not a multiple of sqrt(c), which would pass f = 0.02 at c = 1e-2.
  for (double c : {1e-2, 1e-4, 1e-6}) {
    const Vec3 j = direction_from_cos(c, pi / 2);  // in the cross-section
    EXPECT_NEAR(m.f(n, j), 1.0 / pi, 0.5 * c) << c;
  }
  // On the horizon beta is floored at 1e-6: the same limit as c = 1e-6.
  EXPECT_NEAR(m.f(n, direction_from_cos(0.0, pi / 2)), 1.0 / pi, 0.5e-6);
}

// --- creases -------------------------------------------------------------------------------------
/// Scan step in longitude, and how far from the horizon the scans stay (f grows like
/// beta^{-1/2} and theta_s like sqrt(beta) at grazing: steep but smooth).
constexpr double kScanStep = 2.5e-4;
constexpr double kScanMargin = 0.1;
/// A kink is an isolated spike of the second difference: |D2(phi) - (D2(phi-3s) + D2(phi+3s))/2|/s
/// estimates the jump of df/dphi at a kink within a step s, and is O(s^3 d4f/dphi4) elsewhere.
/// Kinks larger than this fraction of max f per radian are detected.
constexpr double kKinkDetect = 0.01;
/// A listed kink must show a jump of df/dphi of at least this fraction of max f per radian
/// (one-sided slopes 1e-9 from the crease over 1e-6), a listed C1 crease at most kC1Slope.
constexpr double kKinkReal = 2e-4;
constexpr double kC1Slope = 5e-5;
/// Jumps of f larger than this fraction of max f (refined by bisection) would be reported.
constexpr double kJump = 1e-3;

/// k at longitude phi about +x (phi = atan2(-k_y, k_z), models/model.h) and latitude t.
Vec3 on_longitude(double phi, double t) {
  return {std::sin(t), -std::cos(t) * std::sin(phi), std::cos(t) * std::cos(phi)};
}

struct ScanResult {
  int kinks_detected = 0, kinks_listed = 0, c1_listed = 0, jumps = 0;
  double weakest_listed_kink = INFINITY, strongest_c1 = 0.0;
};

void scan(const PoulinFournier& m, const Vec3& fixed, Varying varying, double t, ScanResult& r) {
  auto g = [&](double phi) {
    const Vec3 k = on_longitude(phi, t);
    return varying == Varying::incident ? m.f(k, fixed) : m.f(fixed, k);
  };
  const MassHints hints = m.mass_hints(fixed, varying);
  ASSERT_EQ(hints.crease_axis, Vec3(1.0, 0.0, 0.0));
  const std::vector<double>& listed = hints.crease_longitudes;
  ASSERT_TRUE(std::is_sorted(listed.begin(), listed.end()));
  for (double phi : listed) ASSERT_TRUE(phi > -pi / 2 && phi < pi / 2) << phi;
  const std::vector<PfCrease> kinds = m.creases(fixed);
  ASSERT_EQ(kinds.size(), listed.size());

  const double lo = -pi / 2 + kScanMargin, hi = pi / 2 - kScanMargin;
  const int count = static_cast<int>((hi - lo) / kScanStep);
  std::vector<double> v(count + 1);
  for (int k = 0; k <= count; ++k) v[k] = g(lo + k * kScanStep);
  const double scale = *std::max_element(v.begin(), v.end());
  ASSERT_GT(scale, 0.0);
  auto near_listed = [&](double phi, double tol) {
    return std::any_of(listed.begin(), listed.end(), [&](double c) { return std::abs(c - phi) <= tol; });
  };
  // kinks: isolated spikes of the second difference, each near a listed crease
  std::vector<double> D2(count + 1, 0.0);
  for (int k = 1; k < count; ++k) D2[k] = v[k + 1] - 2 * v[k] + v[k - 1];
  std::vector<double> K(count + 1, 0.0);
  for (int k = 4; k + 4 <= count; ++k) K[k] = std::abs(D2[k] - 0.5 * (D2[k - 3] + D2[k + 3])) / kScanStep;
  for (int k = 5; k + 5 <= count; ++k) {
    if (!(K[k] > kKinkDetect * scale && K[k] >= K[k - 1] && K[k] > K[k + 1])) continue;  // local maxima
    ++r.kinks_detected;
    const double phi = lo + k * kScanStep;
    EXPECT_TRUE(near_listed(phi, 4 * kScanStep))
        << m.spec() << ": unlisted kink at phi=" << phi << " (jump of f' ~ " << K[k] / scale << " max f/rad), t=" << t;
  }
  // jumps: refine every large step by bisection
  for (int k = 0; k < count; ++k) {
    if (!(std::abs(v[k + 1] - v[k]) > kJump * scale)) continue;
    double a = lo + k * kScanStep, b = a + kScanStep, ga = v[k], gb = v[k + 1];
    for (int it = 0; it < 40 && std::abs(gb - ga) > kJump * scale; ++it) {
      const double c = 0.5 * (a + b), gc = g(c);
      if (std::abs(gc - ga) > std::abs(gb - gc)) {
        b = c;
        gb = gc;
      } else {
        a = c;
        ga = gc;
      }
    }
    if (std::abs(gb - ga) > kJump * scale) {
      ++r.jumps;
      EXPECT_TRUE(near_listed(a, 1e-9)) << m.spec() << ": unlisted jump at phi=" << a;
    }
  }
  // each listed crease: a real kink, or C1 (f' continuous) as declared
  for (std::size_t c = 0; c < kinds.size(); ++c) {
    const double phi = kinds[c].longitude;
    if (phi < lo || phi > hi) continue;
    const bool isolated = (c == 0 || phi - kinds[c - 1].longitude > 1e-4) &&
                          (c + 1 == kinds.size() || kinds[c + 1].longitude - phi > 1e-4);
    if (!isolated) continue;
    const double eps = 1e-9, eta = 1e-6;
    const double left = (g(phi - eps) - g(phi - eps - eta)) / eta, right = (g(phi + eps + eta) - g(phi + eps)) / eta;
    const double jump = std::abs(right - left) / scale;
    if (kinds[c].kink) {
      ++r.kinks_listed;
      r.weakest_listed_kink = std::min(r.weakest_listed_kink, jump);
      EXPECT_GE(jump, kKinkReal) << m.spec() << ": listed kink at phi=" << phi << " is not one, t=" << t;
    } else {
      ++r.c1_listed;
      r.strongest_c1 = std::max(r.strongest_c1, jump);
      EXPECT_LE(jump, kC1Slope) << m.spec() << ": listed C1 crease at phi=" << phi << " has a kink, t=" << t;
    }
  }
}

TEST(PoulinFournier, EveryKinkLiesOnAListedCreaseAndEveryListedCreaseIsReal) {
  ScanResult r;
  for (Geometry g : {Geometry{2.5, 0.2}, Geometry{1.5, 0.0}, Geometry{2.0, 0.0}, Geometry{4.0, 0.5}}) {
    const PoulinFournier m(0.6, 0.4, 20.0, g.d, g.h);
    for (const Vec3& fixed : {dir_deg(50, 75), dir_deg(70, 250), dir_deg(20, 10), dir_deg(80, 100)})
      for (double t : {0.0, 0.6})
        for (Varying varying : {Varying::incident, Varying::outgoing}) scan(m, fixed, varying, t, r);
  }
  std::printf(
      "creases: %d kinks detected (all on listed creases); listed kinks %d (weakest f' jump %.3g max f/rad), "
      "listed C1 creases %d (largest f' jump %.3g); jumps %d\n",
      r.kinks_detected, r.kinks_listed, r.weakest_listed_kink, r.c1_listed, r.strongest_c1, r.jumps);
  EXPECT_GT(r.kinks_detected, 0);
  EXPECT_EQ(r.jumps, 0);  // f is continuous: its creases are kinks
}

TEST(PoulinFournier, PlanesHaveNoCreasesAndHighlightsHavePeaks) {
  const PoulinFournier plane(0.5, 0.5, 20.0, 0.0, 0.5);
  const MassHints none = plane.mass_hints(dir_deg(30, 40), Varying::outgoing);
  EXPECT_TRUE(none.crease_longitudes.empty());
  EXPECT_EQ(none.crease_axis, Vec3(0.0, 0.0, 0.0));
  ASSERT_EQ(none.peaks.size(), 1u);
  EXPECT_NEAR(glm::length(none.peaks[0].direction - mirror(dir_deg(30, 40))), 0.0, 1e-15);

  const PoulinFournier m(0.5, 0.5, 100.0, 2.5, 0.2);
  const Vec3 i = dir_deg(40, 30);
  const MassHints hints = m.mass_hints(i, Varying::outgoing);
  ASSERT_EQ(hints.peaks.size(), 5u);
  for (const Peak& p : hints.peaks) {
    EXPECT_NEAR(p.width, 0.2, 1e-15);  // 2/sqrt(n)
    EXPECT_NEAR(glm::length(p.direction), 1.0, 1e-15);
    EXPECT_NEAR(p.direction.x, -i.x, 1e-15);  // on the highlight cone j_x = -i_x
  }
  // the highlight really is there: f along the cone beats f off it
  const Vec3 on = hints.peaks[2].direction, off = glm::normalize(on + Vec3(0.3, 0.0, 0.0));
  EXPECT_GT(m.f(i, on), 2 * m.f(i, off));
  EXPECT_TRUE(PoulinFournier(1.0, 0.0, 1.0, 2.5, 0.2).mass_hints(i, Varying::outgoing).peaks.empty());
}

// --- registry -------------------------------------------------------------------------------------
using testing_support::expect_input_error;

TEST(PoulinFournier, RegistryEntryValidatesParameters) {
  const ModelInfo& info = find_model("poulin-fournier");
  EXPECT_FALSE(info.traits.isotropic);
  EXPECT_TRUE(info.traits.reciprocal);
  EXPECT_EQ(info.traits.energy, EnergyClass::plausible);
  ParamValues defaults;
  for (const ParamInfo& p : info.parameters) {
    EXPECT_FALSE(p.meaning.empty()) << p.name;
    EXPECT_NO_THROW(validate_param(info, p, p.default_value)) << p.name;
    defaults[p.name] = p.default_value;
  }
  ASSERT_EQ(defaults.size(), 5u);
  const ModelPtr m = info.make(defaults);
  EXPECT_EQ(m->spec(), "poulin-fournier:kd=0.5,ks=0.3,n=20,d=2.5,h=0.2");
  EXPECT_EQ(parse_model("poulin-fournier")->spec(), m->spec());
  EXPECT_EQ(m->traits().isotropic, info.traits.isotropic);
  EXPECT_EQ(m->traits().reciprocal, info.traits.reciprocal);
  EXPECT_EQ(m->traits().energy, info.traits.energy);
  expect_input_error("poulin-fournier:d=-1", {"poulin-fournier", "d=-1", "[0, 100]"});
  expect_input_error("poulin-fournier:d=101", {"d=101", "[0, 100]"});
  expect_input_error("poulin-fournier:h=1.5", {"h=1.5", "[0, 1]"});
  expect_input_error("poulin-fournier:n=0.5", {"n=0.5", "[1, 10000]"});
  expect_input_error("poulin-fournier:kd=0.8,ks=0.5", {"kd=0.8", "ks=0.5", "kd + ks <= 1"});
  expect_input_error("poulin-fournier:spacing=2", {"unknown parameter 'spacing'"});
}

// --- energy ----------------------------------------------------------------------------------------
/// Albedo by the engine's cubature. It has no crease-aware panels yet (MassHints::crease_longitudes
/// awaits the coordinator's integrator change), so the tolerance is modest.
constexpr double kAlbedoCubatureTol = 1e-5;

TEST(PoulinFournier, AlbedoAtMostTheLocalAlbedo) {
  for (Geometry g : {Geometry{2.5, 0.2}, Geometry{2.0, 0.0}, Geometry{1.5, 0.0}}) {
    for (auto [kd, ks, n] : {std::tuple{1.0, 0.0, 1.0}, std::tuple{0.0, 1.0, 1.0}}) {
      const PoulinFournier m(kd, ks, n, g.d, g.h);
      for (double c : {1.0, 0.7, 0.3, 0.05}) {
        const Estimate e = albedo(m, direction_from_cos(c, 1.2), testing_support::cubature_options(kAlbedoCubatureTol));
        std::printf("%s cos_i=%-4g albedo=%.6f +- %.1e (%lld evaluations%s)\n", m.spec().c_str(), c, e.value, e.error,
                    static_cast<long long>(e.evaluations), e.converged ? "" : ", NOT converged");
        EXPECT_LE(e.value, kd + ks + 10 * kAlbedoCubatureTol) << m.spec() << " cos_i=" << c;
        EXPECT_GT(e.value, 0.0);
      }
    }
  }
}

/// Tolerance asked of the engine for the 1-D comparison.
constexpr double kEngineTol = 1e-8;

TEST(PoulinFournier, DiffuseAlbedoReducesToOneDimensionAndTheEngineIsHonest) {
  // With ks = 0, f(i, j) depends on j only through its longitude phi about the tangent, so with
  // j = (sin t, -cos t sin phi, cos t cos phi), dj = cos t dt dphi and j.n = cos t cos phi:
  //   a(i) = ∫ cos^2 t dt ∫ f(i, j(phi)) cos phi dphi = (pi/2) ∫_{-pi/2}^{pi/2} f(i, j(phi, 0)) cos phi dphi,
  // a 1-D integral that Gauss-Kronrod does to 1e-12 when split at the listed creases. The
  // engine's cubature (no crease cuts yet) must agree within its own error estimate.
  for (Geometry g : {Geometry{2.5, 0.2}, Geometry{2.0, 0.0}, Geometry{1.5, 0.0}}) {
    const PoulinFournier m(1.0, 0.0, 1.0, g.d, g.h);
    for (const Vec3& i : {dir_deg(0, 0), dir_deg(60, 90), dir_deg(75, 30)}) {
      std::vector<double> cuts{-pi / 2};
      for (double c : m.crease_longitudes(i)) cuts.push_back(c);
      cuts.push_back(pi / 2);
      double reference = 0.0;
      for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
        reference +=
            gk([&](double phi) { return m.f(i, on_longitude(phi, 0.0)) * std::cos(phi); }, cuts[k], cuts[k + 1]);
      reference *= pi / 2;
      const Estimate e = albedo(m, i, testing_support::cubature_options(kEngineTol));
      std::printf("%s i.z=%.3f: albedo %.12f (1-D), engine %.12f +- %.1e in %lld evaluations\n", m.spec().c_str(), i.z,
                  reference, e.value, e.error, static_cast<long long>(e.evaluations));
      EXPECT_TRUE(e.converged);
      EXPECT_NEAR(e.value, reference, e.error + 1e-11) << m.spec() << " i.z=" << i.z;
      EXPECT_LT(reference, 1.0);
    }
  }
}

}  // namespace
}  // namespace ganzfeld
