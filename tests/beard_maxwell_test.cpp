// Beard–Maxwell (models/beard_maxwell.h): the shadowing/obscuration factor and the Fresnel ratio at
// their limits, the monostatic identity f_fs(i, i) = rho_fs(theta_N), a straight transcription
// with SCATMECH's angles, the pure Lambert + volumetric limit, the volumetric albedo's closed
// form, the laws g, h, a by the engine (integrate/laws.h) against independent brute-force
// quadrature, finiteness at the extremes, reciprocity and isotropy measured, the energy class,
// mass hints, the first-surface table (format, refusals, agreement with the built-in lobe), and
// parameter validation through the spec parser.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "tests/temp_dir.h"
#include "tests/test_support.h"

#include "integrate/laws.h"
#include "models/beard_maxwell.h"
#include "models/classic_models.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;
using GK = boost::math::quadrature::gauss_kronrod<double, 61>;

// --- tolerances --------------------------------------------------------------------------------
/// A dozen double operations (atan2, exp, the complex Fresnel) against a long-double
/// transcription with other formulas for the same angles: rounding only, ~1e-15; allow 1e-12.
constexpr double kTranscriptionRel = 1e-12;
/// The monostatic identity at theta_N up to 1.4 rad: exp(-tan^2/m^2) with an exponent up to ~200
/// turns the ~1 ulp difference between our tan^2 (from the vector) and std::tan into ~1e-13 relative.
constexpr double kMonostaticRel = 1e-12;
/// Rotating i and j about n moves their components by ~1 ulp; the sharpest lobe tested
/// (m = 0.05: d ln f/d theta_N ~ 2 theta_N/m^2 ~ 1e2 near the peak) amplifies that: allow 1e-10.
constexpr double kRotationRel = 1e-10;
/// The engine's default tolerance (CubatureOptions::abs_tol = 1e-9, a raw Kronrod–Gauss bound),
/// plus the brute force's own ~5e-12 (kBruteRel below; measured agreement 1e-11 to 2e-11):
/// allow ten times the engine's tolerance.
constexpr double kLawTol = 1e-8;
/// The engine asked for kCubatureTol in the albedo sweeps (speed); compare with ten times that.
constexpr double kCubatureTol = 1e-7;
constexpr double kAlbedoTol = 10 * kCubatureTol;
/// A first-surface table sampled every 0.1 deg (h = 1.75e-3 rad) from the built-in lobe
/// (m = 0.15): even linear interpolation of exp(-x^2/m^2) would err by only (h^2/8)|v''/v| <=
/// (h^2/8)(4x^2/m^4 + 2/m^2) = 6e-4 relative out to x = 3m, where f is compared (the monotone
/// cubic does better); allow 1e-3 relative on f and 1e-4 absolute on h.
constexpr double kTableRel = 1e-3;
constexpr double kTableLawTol = 1e-4;

/// The brute force's nested 61-point Gauss–Kronrod: relative tolerance per 1-D integral and
/// bisection depth (the conical kinks of SO and theta_N at the mirror and the source converge
/// slowly; 1e-11 relative is ~5e-12 absolute on h ~ 0.45, far inside kLawTol).
constexpr double kBruteRel = 1e-11;
constexpr unsigned kBruteDepth = 12;

CubatureOptions engine() { return CubatureOptions{}; }  // abs_tol 1e-9

std::shared_ptr<const BeardMaxwell> bm(const std::string& params = "") {
  const ModelPtr m = parse_model(params.empty() ? "beard-maxwell" : "beard-maxwell:" + params);
  auto p = std::dynamic_pointer_cast<const BeardMaxwell>(m);
  EXPECT_TRUE(p) << params;
  return p;
}

/// Materials spanning the ranges: the defaults, a rough metal, a sharp dielectric, extremes.
const std::vector<std::string> kMaterials{
    "",
    "n=0.2,k=3,b=0.9,m=0.4,tau=5,omega=10,rho_d=0,rho_v=0.02",
    "n=1.5,k=0,b=0.04,m=0.05,tau=50,omega=1,rho_d=0.2,rho_v=0",
    "n=10,k=20,b=1,m=1,tau=0.01,omega=0.01,rho_d=1,rho_v=1",
    "n=1.003,k=0,b=1,m=0.01,tau=1e6,omega=1e6,rho_d=0,rho_v=0",
};

std::vector<Vec3> test_directions() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> dirs;
  for (double c : {0.0, 1e-300, 1e-12, 1e-6, 1e-3, 0.2, 0.5, 0.9, 1.0 - 1e-12, 1.0})
    for (double phi : {0.0, 0.5 * pi, pi, 1.5 * pi}) dirs.push_back(direction_from_cos(c, phi));
  for (int k = 0; k < 40; ++k) dirs.push_back(direction_from_cos(u(rng), 2 * pi * u(rng)));
  for (double c : {0.05, 0.4, 0.8}) {  // near-mirror pairs
    dirs.push_back(direction_from_cos(c, 0.3));
    dirs.push_back(direction_from_cos(c * 1.001, 0.3 + pi));
  }
  return dirs;
}

Vec3 rotate_z(const Vec3& v, double a) {
  return {std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z};
}

/// The Beckmann distribution D(theta_N) = exp(-tan^2/m^2)/(pi m^2 cos^4), written out.
double beckmann(double theta_N, double m) {
  const double t = std::tan(theta_N), c = std::cos(theta_N);
  return std::exp(-t * t / (m * m)) / (pi * m * m * c * c * c * c);
}

// --- SO and the Fresnel ratio -------------------------------------------------------------------
TEST(BeardMaxwell, ShadowingObscurationLimitsAndAValue) {
  for (double theta_N : {0.0, 0.1, 0.7, 1.5})
    for (double beta : {0.0, 0.2, 1.0, pi / 2}) {
      const double so = beard_maxwell_so(theta_N, beta, 0.25, 0.7);
      EXPECT_GT(so, 0.0);
      EXPECT_LE(so, 1.0);
      if (beta == 0.0 || theta_N == 0.0) { EXPECT_EQ(so, 1.0) << theta_N << " " << beta; }
      // Omega -> infinity: no obscuration; tau -> infinity: no shadowing decay
      // (1 - SO = x (1 - e^{-2 beta/tau})/(1 + x) <= x = theta_N/Omega, and <= 2 beta/tau x)
      for (double big : {1e6, 1e12}) {
        EXPECT_LE(1.0 - beard_maxwell_so(theta_N, beta, 0.25, big), theta_N / big + 1e-15);  // + a few ulps of 1
        EXPECT_LE(1.0 - beard_maxwell_so(theta_N, beta, big, 0.7), 2 * beta / big * theta_N / 0.7 + 1e-15);
      }
      // tau -> 0 with beta > 0: the full obscuration 1/(1 + theta_N/Omega)
      if (beta > 0.0) { EXPECT_NEAR(beard_maxwell_so(theta_N, beta, 1e-6, 0.7), 1.0 / (1.0 + theta_N / 0.7), 1e-15); }
    }
  // SCATMECH's defaults (tau = 0.25, Omega = 0.7 rad) at theta_N = 0.3, beta = 0.2, by hand
  const double x = 0.3 / 0.7;
  EXPECT_NEAR(beard_maxwell_so(0.3, 0.2, 0.25, 0.7), (1 + x * std::exp(-1.6)) / (1 + x), 1e-16);
  // decreasing in beta for theta_N > 0
  double prev = 1.0;
  for (double beta = 0.05; beta < pi / 2; beta += 0.05) {
    const double so = beard_maxwell_so(0.5, beta, 0.25, 0.7);
    EXPECT_LT(so, prev);
    prev = so;
  }
}

TEST(BeardMaxwell, FresnelRatioIsOneAtBetaZeroAndOneOverR0AtGrazing) {
  for (const std::string& p : kMaterials) {
    const auto m = bm(p);
    EXPECT_EQ(m->fresnel_ratio(1.0), 1.0) << p;
  }
  const auto m = bm("n=1.5,k=0");
  EXPECT_NEAR(m->fresnel_ratio(0.0), 1.0 / 0.04, 1e-12);  // R(pi/2) = 1, R(0) = (0.5/2.5)^2
}

// --- the formula ------------------------------------------------------------------------------
TEST(BeardMaxwell, MonostaticGeometryReturnsTheFirstSurfaceFunction) {
  // i = j: beta = 0 and theta_N = theta, so R(beta)/R(0) = SO = cos^2 theta_N/(mu_i mu_j) = 1 and
  // the first-surface term is rho_fs(theta) itself: B D(theta)/(4 cos^2 theta) for the stand-in.
  const auto m = bm("b=0.3,m=0.4,n=1.3,k=0.5,tau=3,omega=7");
  for (double theta : {0.0, 0.1, 0.5, 1.0, 1.4}) {
    const Vec3 i = direction(theta, 0.7);
    const double expected = 0.3 * beckmann(theta, 0.4) / (4 * std::cos(theta) * std::cos(theta));
    EXPECT_NEAR(m->first_surface(i, i), expected, kMonostaticRel * expected) << theta;
  }
}

/// Westlund & Meyer's form of the NEF model, evaluated with SCATMECH's expressions for theta_N
/// and beta (torrspar.cpp, Maxwell_Beard_Shadow_Function) from (theta_i, theta_s, phi_s), where
/// the source lies at azimuth pi and phi_s = 0 is the forward specular plane, and with the
/// dielectric Fresnel equations written out (k = 0).
long double transcribed(double theta_i, double theta_s, double phi_s, double n, double b, double m, double tau_deg,
                        double omega_deg, double rho_D, double rho_V) {
  using L = long double;
  const L PI = std::numbers::pi_v<long double>;
  const L si = std::sin(L(theta_i)), ss = std::sin(L(theta_s)), ci = std::cos(L(theta_i)), cs = std::cos(L(theta_s));
  const L temp = si * si - 2 * si * ss * std::cos(L(phi_s)) + ss * ss;
  const L thetan = std::atan(temp > 0 ? std::sqrt(temp) / (ci + cs) : 0);
  const L cos_angle = std::sqrt((1 - si * ss * std::cos(L(phi_s)) + ci * cs) / 2);
  const L beta = cos_angle < 1 ? std::acos(cos_angle) : 0;
  const L tau = tau_deg * PI / 180, omega = omega_deg * PI / 180;
  const L SO = (1 + (thetan / omega) * std::exp(-2 * beta / tau)) / (1 + thetan / omega);
  auto R = [n](L c) {  // unpolarized Fresnel, real index
    const L sin_t = std::sqrt(1 - c * c) / n, ct = std::sqrt(1 - sin_t * sin_t);
    const L rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
    return (rs * rs + rp * rp) / 2;
  };
  const L tn = std::tan(thetan), cn = std::cos(thetan);
  const L D = std::exp(-tn * tn / (L(m) * m)) / (PI * m * m * cn * cn * cn * cn);
  const L rho_fs = b * D / (4 * cn * cn);
  return R(cos_angle) / R(1) * rho_fs * cn * cn / (ci * cs) * SO + rho_D + 2 * rho_V / (ci + cs);
}

TEST(BeardMaxwell, MatchesAStraightTranscription) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto m = bm("n=1.7,k=0,b=0.6,m=0.3,tau=12,omega=25,rho_d=0.05,rho_v=0.03");
  int compared = 0;
  for (int t = 0; t < 400; ++t) {
    const double ti = std::acos(0.02 + 0.98 * u(rng)), ts = std::acos(0.02 + 0.98 * u(rng));
    const double phi_s = t % 2 ? 2 * pi * u(rng) : 0.5 * (u(rng) - 0.5);  // half near the specular plane
    const Vec3 i{-std::sin(ti), 0.0, std::cos(ti)};
    const Vec3 j{std::sin(ts) * std::cos(phi_s), std::sin(ts) * std::sin(phi_s), std::cos(ts)};
    const long double ref = transcribed(ti, ts, phi_s, 1.7, 0.6, 0.3, 12, 25, 0.05, 0.03);
    EXPECT_NEAR(m->f(i, j) / ref, 1.0, kTranscriptionRel) << ti << " " << ts << " " << phi_s;
    ++compared;
  }
  EXPECT_EQ(compared, 400);
}

TEST(BeardMaxwell, FirstSurfaceScaleZeroIsLambertPlusVolumetric) {
  const auto m = bm("b=0,rho_d=0.07,rho_v=0.04");
  for (const Vec3& i : test_directions())
    for (const Vec3& j : test_directions()) {
      if (i.z < 0 || j.z < 0) continue;
      EXPECT_EQ(m->first_surface(i, j), 0.0);
      EXPECT_EQ(m->f(i, j), 0.07 + 2 * 0.04 / std::max(i.z + j.z, kGrazingCosFloor));
    }
}

// --- energy: closed forms and quadrature ----------------------------------------------------------
TEST(BeardMaxwell, LambertAndVolumetricAlbedosMatchTheirClosedForms) {
  // a = pi rho_D + 4 pi rho_V (1 - mu ln(1 + 1/mu)): ∫ 2 rho_V mu/(mu_i + mu) d omega, mu in [0, 1].
  const double rho_D = 0.08, rho_V = 0.05;
  const auto m = bm("b=0,rho_d=0.08,rho_v=0.05");
  for (double mu : testing_support::kIncidenceCosines) {
    const Estimate a = albedo(*m, direction_from_cos(mu, 0.4), testing_support::cubature_options(kCubatureTol));
    ASSERT_TRUE(a.converged) << mu;
    const double closed = pi * rho_D + 4 * pi * rho_V * (1 - mu * std::log1p(1 / mu));
    EXPECT_NEAR(a.value, closed, kAlbedoTol) << mu;
  }
}

TEST(BeardMaxwell, NormalIncidenceAlbedoMatchesOneDimensionalQuadrature) {
  // i = n: theta_N = beta = theta_h and d omega_r = 4 cos theta_h d omega_h, so
  // a(n) = B ∫_0^{pi/4} [R(theta_h)/R(0)] D(theta_h) SO(theta_h, theta_h) cos theta_h 2 pi sin theta_h d theta_h.
  struct Case {
    double n, k, B, slope, tau_deg, omega_deg;
  };
  for (const Case c : {Case{1.5, 0, 0.5, 0.3, 20, 30}, Case{0.2, 3, 0.9, 0.6, 5, 10}}) {
    const auto m = bm("n=" + format_number(c.n) + ",k=" + format_number(c.k) + ",b=" + format_number(c.B) +
                      ",m=" + format_number(c.slope) + ",tau=" + format_number(c.tau_deg) +
                      ",omega=" + format_number(c.omega_deg) + ",rho_d=0,rho_v=0");
    const double B = c.B, slope = c.slope, tau = c.tau_deg * pi / 180, omega = c.omega_deg * pi / 180;
    // f's 1/(mu_i mu_j) is floored at kGrazingCosFloor: (k·n) f ramps to 0 across k·n = cos 2 theta_h
    // < kGrazingCosFloor, at the end of the interval (a break there).
    const auto integrand = [&](double th) {
      const double ramp = std::min(1.0, std::cos(2 * th) / kGrazingCosFloor);
      return B * m->fresnel_ratio(std::cos(th)) * beckmann(th, slope) * beard_maxwell_so(th, th, tau, omega) *
             std::cos(th) * 2 * pi * std::sin(th) * ramp;
    };
    const double ramp_start = 0.5 * std::acos(kGrazingCosFloor);
    // The ramp holds ~1e-8 of the albedo, linear in cos 2 theta_h: to 1e-6 of itself.
    const double expected =
        GK::integrate(integrand, 0.0, ramp_start, 20, 1e-13) + GK::integrate(integrand, ramp_start, pi / 4, 5, 1e-6);
    const Estimate a = albedo(*m, Vec3{0, 0, 1}, engine());
    ASSERT_TRUE(a.converged);
    EXPECT_NEAR(a.value, expected, kLawTol) << m->spec();
  }
}

/// ∫_0^{2pi} ∫_0^{theta_max(phi)} F(k) sin theta d theta d phi by nested 61-point Gauss–Kronrod
/// (Boost, adaptive), with the given cuts in phi and theta — independent of the engine.
template <class F, class ThetaMax>
double brute_force(const F& F_, const ThetaMax& theta_max, std::vector<double> phi_cuts, double theta_cut) {
  std::sort(phi_cuts.begin(), phi_cuts.end());
  // f's cosines are floored at kGrazingCosFloor: (k·n) f ramps to 0 across k·n < kGrazingCosFloor.
  const double floor_cut = std::acos(kGrazingCosFloor);
  const auto outer = [&](double phi) {
    const double top = theta_max(phi);
    const auto inner = [&](double theta) { return F_(direction(theta, phi)) * std::sin(theta); };
    double total = 0.0, from = 0.0;
    if (theta_cut > 0 && theta_cut < std::min(top, floor_cut)) {
      total += GK::integrate(inner, 0.0, theta_cut, kBruteDepth, kBruteRel);
      from = theta_cut;
    }
    if (top <= floor_cut) return total + GK::integrate(inner, from, top, kBruteDepth, kBruteRel);
    // The ramp holds ~1e-6 of the integral, linear in k·n: to 1e-6 of itself.
    return total + GK::integrate(inner, from, floor_cut, kBruteDepth, kBruteRel) +
           GK::integrate(inner, floor_cut, top, 5, 1e-6);
  };
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < phi_cuts.size(); ++k)
    total += GK::integrate(outer, phi_cuts[k], phi_cuts[k + 1], kBruteDepth, kBruteRel);
  return total;
}

TEST(BeardMaxwell, LawsByTheEngineMatchBruteForceQuadrature) {
  const auto hemisphere = [](double) { return pi / 2; };
  for (const std::string& p :
       {std::string(""), std::string("n=0.2,k=3,b=0.9,m=0.4,tau=5,omega=10,rho_d=0,rho_v=0.02")}) {
    const auto m = bm(p);
    const double theta = 60 * pi / 180;
    const Vec3 fixed = direction(theta, 0.0);
    // h(j) = ∫ f(k, j)(k.n) dk and a(i) = ∫ f(i, k)(k.n) dk; the mirror (phi = pi) and retro
    // (phi = 0) kinks lie on the phi cuts, the lobe's latitude on the theta cut.
    const double h_ref =
        brute_force([&](const Vec3& k) { return m->f(k, fixed) * k.z; }, hemisphere, {0.0, pi, 2 * pi}, theta);
    const double a_ref =
        brute_force([&](const Vec3& k) { return m->f(fixed, k) * k.z; }, hemisphere, {0.0, pi, 2 * pi}, theta);
    const Estimate h = darkening(*m, fixed, engine()), a = albedo(*m, fixed, engine());
    ASSERT_TRUE(h.converged && a.converged);
    EXPECT_NEAR(h.value, h_ref, kLawTol) << p;
    EXPECT_NEAR(a.value, a_ref, kLawTol) << p;
    EXPECT_NEAR(h.value, a.value, kLawTol) << p;  // reciprocity: h = a
    // g(i, j) = ∫_{k.n > 0, k.i > 0} f(k, j)(k.n) dk: sky pole i at 40 deg, azimuth 0; j at
    // theta 60 deg, azimuth 2.2. For cos phi < 0 the lune's edge is tan theta = cot theta_i/(-cos phi).
    const double ti = 40 * pi / 180;
    const Vec3 sky = direction(ti, 0.0), j = direction(theta, 2.2);
    const auto lune_top = [&](double phi) {
      return std::cos(phi) >= 0 ? pi / 2 : std::atan(std::cos(ti) / (-std::cos(phi) * std::sin(ti)));
    };
    const double g_ref = brute_force([&](const Vec3& k) { return m->f(k, j) * k.z; }, lune_top,
                                     {0.0, pi / 2, 2.2, pi, 1.5 * pi, 2.2 + pi, 2 * pi}, theta);
    const Estimate g = vignetting(*m, sky, j, engine());
    ASSERT_TRUE(g.converged);
    EXPECT_NEAR(g.value, g_ref, kLawTol) << p;
    // and through evaluate_law, as the CLI calls it, against the brute-force references
    EXPECT_NEAR(evaluate_law(*m, Law::g, sky, j, engine()).value, g_ref, kLawTol) << p;
    EXPECT_NEAR(evaluate_law(*m, Law::h, sky, fixed, engine()).value, h_ref, kLawTol) << p;
    std::printf("%s: h(60) = %.12f (brute %.12f, %lld evals), g = %.12f (brute %.12f)\n", m->spec().c_str(), h.value,
                h_ref, h.evaluations, g.value, g_ref);
  }
}

/// With the first surface off (b = 0) f is rho_D + 2 rho_V / max(mu + mu_fixed, kGrazingCosFloor), so
/// with the view on the horizon (mu_fixed = 0) (k·n) f ramps from 0 to 2 rho_V across k·n < 1e-6.
/// On the sphere dk = d(k·n) d(azimuth); the sky of a pole on the horizon is half the azimuths:
/// g = pi (rho_D / 2 + 2 rho_V - rho_V 1e-6) exactly. Without the layer declared the engine's
/// estimate collapsed to 2.5e-15 and it returned pi (rho_D / 2 + 2 rho_V), 3.1e-8 off.
TEST(BeardMaxwell, VolumeTermLayerAtAGrazingFixedDirectionIsHonest) {
  const ModelPtr m = parse_model("beard-maxwell:b=0,rho_d=0.1,rho_v=0.01");
  const double exact = pi * (0.1 / 2 + 2 * 0.01 - 0.01 * kGrazingCosFloor);
  CubatureOptions options;
  options.abs_tol = 1e-8;
  for (const Vec3& j : {Vec3{1, 0, 0}, Vec3{0, 1, 0}}) {
    const Estimate g = vignetting(*m, Vec3{1, 0, 0}, j, options);
    EXPECT_TRUE(g.converged);
    EXPECT_LE(std::abs(g.value - exact), g.error + 1e-14)
        << "j = (" << j.x << ", " << j.y << ", " << j.z << "): engine " << g.value << " ± " << g.error
        << ", closed form " << exact;
  }
}

TEST(BeardMaxwell, NotPlausibleTheFirstSurfaceAlbedoGrowsAtGrazingIncidence) {
  // No shadowing that vanishes at the horizon: a_fs(mu) ~ c/mu as mu -> 0 (cos theta_i in the
  // denominator, SO -> 1 near the mirror). Measured on the first surface alone (rho = 0).
  const auto m = bm("rho_d=0,rho_v=0,b=0.04,m=0.15");
  EXPECT_EQ(m->traits().energy, EnergyClass::not_plausible);
  double prev = 0.0;
  std::vector<double> a_of;
  for (double mu : {0.1, 0.01, 0.001}) {
    const Estimate a = albedo(*m, direction_from_cos(mu, 0.0), testing_support::cubature_options(kCubatureTol));
    ASSERT_TRUE(a.converged) << mu;
    EXPECT_GT(a.value, prev) << mu;
    prev = a.value;
    a_of.push_back(a.value);
    std::printf("beard-maxwell defaults, first surface only: albedo at cos theta_i = %g: %.6f\n", mu, a.value);
  }
  EXPECT_GT(a_of[2], 1.0 + kAlbedoTol);       // the counter-example to plausibility
  EXPECT_NEAR(a_of[2] / a_of[1], 10.0, 1.0);  // ~ 1/mu
  // the defaults themselves stay below 1 away from grazing
  const auto d = bm();
  for (double mu : {1.0, 0.7, 0.3}) {
    const Estimate a = albedo(*d, direction_from_cos(mu, 0.0), testing_support::cubature_options(kCubatureTol));
    EXPECT_LT(a.value, 1.0) << mu;
  }
}

// --- the Model contract ------------------------------------------------------------------------------
TEST(BeardMaxwell, FiniteNonNegativeAndZeroBelowTheHorizon) {
  const auto dirs = test_directions();
  for (const std::string& p : kMaterials) {
    const auto m = bm(p);
    testing_support::expect_finite_non_negative(*m, dirs, p);
    // opposite directions on the horizon: no facet (i + j = 0), only the floored volumetric term
    const Vec3 e = direction_from_cos(0.0, 0.0), w = direction_from_cos(0.0, pi);
    EXPECT_EQ(m->first_surface(e, w), 0.0);
    EXPECT_TRUE(std::isfinite(m->f(e, w)));
    EXPECT_TRUE(std::isfinite(m->f(e, e)));  // i = j on the horizon
  }
}

TEST(BeardMaxwell, ReciprocalBitExactAndIsotropic) {
  const auto dirs = test_directions();
  double worst_recip = 0.0, worst_rot = 0.0;
  for (const std::string& p : kMaterials) {
    const auto m = bm(p);
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        const double a = m->f(i, j), b = m->f(j, i);
        const double scale = std::max({a, b, 1e-300});
        worst_recip = std::max(worst_recip, std::abs(a - b) / scale);
        if (i.z > 1e-3 && j.z > 1e-3 && a > 1e-200)
          worst_rot = std::max(worst_rot, std::abs(m->f(rotate_z(i, 0.7), rotate_z(j, 0.7)) - a) / a);
      }
  }
  std::printf("beard-maxwell: worst reciprocity asymmetry %.3g, worst rotation change %.3g\n", worst_recip, worst_rot);
  EXPECT_EQ(worst_recip, 0.0);
  EXPECT_LE(worst_rot, kRotationRel);
}

TEST(BeardMaxwell, MassHintsSitAtTheMirrorAndTheSource) {
  const auto m = bm("m=0.15,tau=15,rho_v=0.01");
  const Vec3 i = direction_from_cos(0.9, 0.3);
  const MassHints h = m->mass_hints(i, Varying::outgoing);
  ASSERT_GE(h.peaks.size(), 1u);
  EXPECT_NEAR(glm::length(h.peaks[0].direction - mirror(i)), 0.0, 1e-15);
  EXPECT_NEAR(h.peaks[0].width, std::sqrt(2.0) * std::atan(0.15), 1e-15);
  ASSERT_EQ(h.peaks.size(), 2u);  // the retro kink of SO: rho_fs(25.8 deg) is not negligible
  EXPECT_EQ(h.peaks[1].direction, i);
  EXPECT_NEAR(h.peaks[1].width, 15 * pi / 180, 1e-15);
  // The first surface's floored 1/(mu mu_fixed) ramps across k·n < kGrazingCosFloor: kGrazingLayer,
  // the thinnest layer, whatever the fixed direction; without a first surface, rho_V's layer.
  EXPECT_EQ(h.horizon_layer, kGrazingLayer);
  const Vec3 grazing = direction_from_cos(0.05, 0.0);
  EXPECT_EQ(m->mass_hints(grazing, Varying::incident).horizon_layer, kGrazingLayer);
  EXPECT_EQ(bm("b=0,rho_v=0.01")->mass_hints(grazing, Varying::incident).horizon_layer, 0.05);
  EXPECT_EQ(bm("b=0,rho_v=0")->mass_hints(grazing, Varying::incident).horizon_layer, 0.0);
}

// --- the first-surface table ---------------------------------------------------------------------
std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = testing_support::temp_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// The built-in lobe's rho_fs sampled every `step` degrees to 89 as a table file.
std::string table_from_builtin(double B, double slope, double step) {
  std::ostringstream theta, rho;
  theta << "theta_N:";
  rho << "rho_fs:";
  for (double t = 0.0; t <= 89.0 + 1e-9; t += step) {
    const double th = t * pi / 180;
    theta << " " << format_number(t);
    rho << " " << format_number(B * beckmann(th, slope) / (4 * std::cos(th) * std::cos(th)));
  }
  return "ganzfeld-beard-maxwell-first-surface 1\n# sampled from the built-in lobe\n" + theta.str() + "\n" + rho.str() +
         "\n";
}

TEST(BeardMaxwell, FirstSurfaceTableReproducesTheBuiltInLobe) {
  const std::string path = write_file("fs.txt", table_from_builtin(0.04, 0.15, 0.1));
  const auto table = bm("file=" + path);
  const auto builtin = bm();
  EXPECT_EQ(table->spec(), "beard-maxwell:file=" + path + ",n=1.5,k=0,tau=15,omega=40,rho_d=0.1,rho_v=0.01");
  EXPECT_EQ(parse_model(table->spec())->spec(), table->spec());  // round trip
  for (const Vec3& i : test_directions())
    for (const Vec3& j : test_directions()) {
      if (i.z < 0.05 || j.z < 0.05) continue;
      const double a = builtin->first_surface(i, j), b = table->first_surface(i, j);
      const Vec3 s = glm::normalize(i + j);
      if (std::atan2(std::hypot(s.x, s.y), s.z) <= 3 * 0.15) {  // theta_N within 3 m
        EXPECT_NEAR(b / a, 1.0, kTableRel) << i.z << " " << j.z;
      }
      EXPECT_NEAR(table->volumetric(i, j), builtin->volumetric(i, j), 0.0);
    }
  for (double theta_deg : {0.0, 30.0, 60.0}) {
    const Vec3 j = direction(theta_deg * pi / 180, 0.0);
    const CubatureOptions o = testing_support::cubature_options(1e-6);
    EXPECT_NEAR(darkening(*table, j, o).value, darkening(*builtin, j, o).value, kTableLawTol) << theta_deg;
  }
  // The hinted width follows the table: sqrt(2) x the theta_N where rho_fs cos^2 theta_N =
  // B exp(-tan^2/m^2)/(4 pi m^2 cos^4) has fallen by 1/e (by bisection), within a node.
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (std::exp(-std::pow(std::tan(mid) / 0.15, 2)) / std::pow(std::cos(mid), 4) > std::exp(-1.0) ? lo : hi) = mid;
  }
  EXPECT_NEAR(table->mass_hints(Vec3{0, 0, 1}, Varying::outgoing).peaks[0].width, std::sqrt(2.0) * lo,
              std::sqrt(2.0) * 0.1 * pi / 180);
  // (the built-in hint is sqrt(2) atan m, the 1/e width of exp(-tan^2/m^2) alone: 2% narrower)
  EXPECT_NEAR(builtin->mass_hints(Vec3{0, 0, 1}, Varying::outgoing).peaks[0].width / (std::sqrt(2.0) * lo), 1.0, 0.03);
}

TEST(BeardMaxwell, FirstSurfaceTableInterpolatesMonotoneCubicAndClamps) {
  // Two nodes: the straight line between them, held at the end values outside.
  const std::string two =
      write_file("two.txt", "ganzfeld-beard-maxwell-first-surface 1\ntheta_N: 10 30  # degrees\nrho_fs: 2 1\n");
  const auto m2 = bm("file=" + two + ",rho_d=0,rho_v=0,n=1.5");
  for (double theta_deg : {0.0, 10.0, 20.0, 30.0, 50.0}) {
    const Vec3 i = direction(theta_deg * pi / 180, 0.0);  // monostatic: f = rho_fs(theta)
    const double expected = theta_deg <= 10 ? 2.0 : theta_deg >= 30 ? 1.0 : 2.0 - (theta_deg - 10) / 20;
    EXPECT_NEAR(m2->f(i, i), expected, 1e-13) << theta_deg;
  }
  // Several nodes with a plateau and a drop to 0: through the nodes, monotone between them (never
  // below 0 or above the neighbours), flat at theta_N = 0, and continuous in slope.
  const std::vector<double> th{0, 2, 5, 10, 20, 40}, v{3, 2.4, 1.1, 0.2, 0.01, 0};
  std::ostringstream text;
  text << "ganzfeld-beard-maxwell-first-surface 1\ntheta_N:";
  for (double t : th) text << " " << t;
  text << "\nrho_fs:";
  for (double x : v) text << " " << x;
  text << "\n";
  const auto m = bm("file=" + write_file("six.txt", text.str()) + ",rho_d=0,rho_v=0");
  const auto rho = [&](double deg) {
    const Vec3 i = direction(deg * pi / 180, 0.0);
    return m->f(i, i);
  };
  for (std::size_t k = 0; k < th.size(); ++k) EXPECT_NEAR(rho(th[k]), v[k], 1e-13) << th[k];
  for (std::size_t k = 0; k + 1 < th.size(); ++k) {
    double prev = rho(th[k]);
    for (int s = 1; s <= 50; ++s) {
      const double x = rho(th[k] + (th[k + 1] - th[k]) * s / 50.0);
      EXPECT_LE(x, prev + 1e-15) << th[k] << " + " << s;  // v decreases: so does the interpolant
      EXPECT_GE(x, 0.0);
      prev = x;
    }
  }
  EXPECT_NEAR(rho(1e-3) - rho(0.0), 0.0, 1e-6);  // slope 0 at theta_N = 0: O(eps^2)
  EXPECT_EQ(rho(60.0), 0.0);                     // held at the last value
  for (double node : {2.0, 5.0, 10.0, 20.0}) {   // C^1: one-sided slopes agree at the nodes
    const double e = 1e-5;
    const double left = (rho(node) - rho(node - e)) / e, right = (rho(node + e) - rho(node)) / e;
    EXPECT_NEAR(left, right, 1e-3 * std::max(1.0, std::abs(left))) << node;
  }
}

TEST(BeardMaxwell, MalformedTablesAndMisusedParametersAreRefusedOnOneLine) {
  const auto refused = [](const std::string& spec, const std::string& needle) {
    testing_support::expect_input_error(spec, {needle});
  };
  const std::string magic = "ganzfeld-beard-maxwell-first-surface 1\n";
  const auto file = [&](const std::string& name, const std::string& body) {
    return "beard-maxwell:file=" + write_file(name, body);
  };
  refused(file("m1.txt", "wrong 1\ntheta_N: 0\nrho_fs: 1\n"), "expected the first line");
  refused(file("m2.txt", magic + "theta_N: 0 10 5\nrho_fs: 1 1 1\n"), "increase");
  refused(file("m3.txt", magic + "theta_N: 0 95\nrho_fs: 1 1\n"), "outside [0, 90] degrees");
  refused(file("m4.txt", magic + "theta_N: 0 10\nrho_fs: 1 -1\n"), "outside [0, 1e+06] 1/sr");
  refused(file("m5.txt", magic + "theta_N: 0 10\nrho_fs: 1\n"), "one rho_fs per theta_N");
  refused(file("m6.txt", magic + "theta_N: 0 10\nrho_fs: 1 x\n"), "not a number");
  refused(file("m7.txt", magic + "theta_N: 0 10\nrho_fs: 1 1\n3\n"), "unexpected content");
  refused(file("m8.txt", magic + "theta_N: 0 10\n"), "missing the 'rho_fs:' line");
  refused("beard-maxwell:file=/nonexistent/fs.txt", "cannot read Beard-Maxwell first-surface table");
  const std::string ok = file("ok.txt", magic + "theta_N: 0 10\nrho_fs: 1 0\n");
  EXPECT_NO_THROW(parse_model(ok));
  refused(ok + ",b=0.5", "b=0.5 has no effect with file=");
  refused(ok + ",m=0.3", "m=0.3 has no effect with file=");
  // parameters: the registry's range messages, and the cross-parameter Fresnel check
  refused("beard-maxwell:tau=0", "beard-maxwell: tau=0 is out of range; allowed: a real number in [0.01, 1e+06]");
  refused("beard-maxwell:rho_v=-1", "rho_v=-1 is out of range");
  refused("beard-maxwell:k=nan", "k=nan is not finite");
  refused("beard-maxwell:alpha=1", "unknown parameter 'alpha' for model 'beard-maxwell'");
  refused("beard-maxwell:n=1,k=0", "allowed: R(0) = ((n-1)^2 + k^2)/((n+1)^2 + k^2) >= 1e-6");
  EXPECT_NO_THROW(parse_model("beard-maxwell:n=1,k=0.01"));
}

TEST(BeardMaxwell, RegisteredWithADocumentedParameterTable) {
  const ModelInfo& info = find_model("beard-maxwell");
  EXPECT_FALSE(info.summary.empty());
  EXPECT_FALSE(info.source.empty());
  EXPECT_TRUE(info.file_optional);
  EXPECT_TRUE(info.make_with_file);
  ASSERT_EQ(info.parameters.size(), 8u);
  for (const ParamInfo& p : info.parameters) {
    EXPECT_FALSE(p.meaning.empty()) << p.name;
    EXPECT_NO_THROW(parse_model("beard-maxwell:" + p.name + "=" + format_number(p.min))) << p.name;
    EXPECT_NO_THROW(parse_model("beard-maxwell:" + p.name + "=" + format_number(p.max))) << p.name;
  }
  const auto d = bm();
  EXPECT_EQ(d->spec(), "beard-maxwell:n=1.5,k=0,b=0.04,m=0.15,tau=15,omega=40,rho_d=0.1,rho_v=0.01");
  for (const std::string& p : kMaterials) {
    const auto m = bm(p);
    EXPECT_EQ(parse_model(m->spec())->spec(), m->spec());
    EXPECT_EQ(m->traits().reciprocal, info.traits.reciprocal);
    EXPECT_EQ(m->traits().isotropic, info.traits.isotropic);
    EXPECT_EQ(m->traits().energy, info.traits.energy);
  }
}

}  // namespace
}  // namespace ganzfeld
