// integrate/: laws against closed forms and against an independent high-order reference, honesty
// of the error estimate, extreme geometries, determinism, reported non-convergence.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <span>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "integrate/laws.h"
#include "models/kp_lobes.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

constexpr double kTol = 1e-10;  // requested absolute tolerance of the cubature under test
// Honesty: the estimate must bound the true error in >= 99.9% of cases.
constexpr double kHonestFraction = 0.999;

CubatureOptions options(double tol = kTol) {
  CubatureOptions o;
  o.abs_tol = tol;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Closed forms (the ones verified correct or corrected in docs/errata.md), on random geometry.
struct Case {
  std::string spec;
  Vec3 i, j;
  double exact;
};

std::vector<Case> closed_form_cases() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Case> cases;
  for (int k = 0; k < 150; ++k) {
    const double c = 2 * u(rng) - 1, mu = u(rng), phi = pi * u(rng), xi = 3 * u(rng);
    const Vec3 i = direction_from_cos(c), j = direction_from_cos(mu, phi);
    cases.push_back({"lambert", i, j, lambert::g(c)});
    cases.push_back({"minnaert:xi=" + std::to_string(xi), i, j, minnaert::g(c, mu, std::stod(std::to_string(xi)))});
    cases.push_back({"backscatter:alpha=1", i, j, backscatter::g_alpha1(i, j)});
    cases.push_back({"asperity:alpha=1", i, j, asperity::g_alpha1(c, mu)});
  }
  return cases;
}

TEST(LawIntegrals, VignettingMatchesClosedFormsWithHonestErrors) {
  const auto cases = closed_form_cases();
  int dishonest = 0;
  for (const auto& cs : cases) {
    const Estimate e = vignetting(*parse_model(cs.spec), cs.i, cs.j, options());
    ASSERT_TRUE(e.converged) << cs.spec;
    EXPECT_NEAR(e.value, cs.exact, kTol) << cs.spec;
    // The closed forms carry ~1e-15 of rounding of their own.
    if (std::abs(e.value - cs.exact) > e.error + 1e-14) ++dishonest;
  }
  EXPECT_LE(dishonest, (1.0 - kHonestFraction) * cases.size());
}

TEST(LawIntegrals, DarkeningAlbedoAndReflectanceMatchClosedForms) {
  for (double xi : {0.0, 1e-6, 0.3, 1.0, 2.7, 50.0}) {
    const Minnaert m(xi);
    for (double mu : {0.0, 1e-6, 0.3, 0.999, 1.0}) {
      const Estimate h = darkening(m, direction_from_cos(mu, 1.0), options());
      const Estimate a = albedo(m, direction_from_cos(mu, 2.0), options());
      EXPECT_NEAR(h.value, minnaert::h(mu, xi), kTol) << xi << " " << mu;
      EXPECT_NEAR(a.value, minnaert::a(mu, xi), kTol) << xi << " " << mu;
      EXPECT_LE(std::abs(h.value - minnaert::h(mu, xi)), h.error + 1e-14);
    }
    const Estimate r = double_diffuse(m, options());
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.value, minnaert::r(xi), kTol) << xi;
  }
  const Specular s1(1);
  for (double mu : {0.0, 0.5, 1.0})
    EXPECT_NEAR(albedo(s1, direction_from_cos(mu), options()).value, specular::a_alpha1_printed(mu), kTol);
}

// ---------------------------------------------------------------------------------------------
// An independent reference: Boost's adaptive Gauss–Kronrod (61 points) nested over the lune,
// written out here from its definition with its own frame, and with break points at the lobe's
// coordinates. It shares no code with integrate/ (the lune map is validated by the closed forms).
double reference_vignetting(const Model& model, const Vec3& i, const Vec3& j, const Vec3& lobe) {
  using boost::math::quadrature::gauss_kronrod;
  const Vec3 n{0, 0, 1};
  Vec3 e = glm::cross(n, i);
  if (glm::length(e) < 1e-300) e = Vec3{0, 1, 0};
  e = glm::normalize(e);
  const Vec3 u = glm::cross(e, n);
  const double phi_lo = std::atan2(glm::length(glm::cross(n, i)), i.z) - pi / 2;
  if (!(phi_lo < pi / 2)) return 0.0;
  const double t_lobe = std::asin(std::clamp(glm::dot(lobe, e), -1.0, 1.0));
  const double phi_lobe = std::atan2(glm::dot(lobe, u), lobe.z);
  auto breaks = [](double lo, double hi, double centre) {
    std::vector<double> b{lo};
    for (double w : {-0.2, -0.05, 0.0, 0.05, 0.2})
      if (centre + w > lo && centre + w < hi) b.push_back(centre + w);
    b.push_back(hi);
    std::sort(b.begin(), b.end());
    return b;
  };
  auto integrate = [](auto&& f, const std::vector<double>& b) {
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < b.size(); ++k)
      sum += gauss_kronrod<double, 61>::integrate(f, b[k], b[k + 1], 6,
                                                  1e-12);  // relative to |f|_1; agrees to ~1e-15 here
    return sum;
  };
  const auto t_breaks = breaks(-pi / 2, pi / 2, t_lobe);
  const auto phi_breaks = breaks(phi_lo, pi / 2, phi_lobe);
  return integrate(
      [&](double t) {
        return integrate(
            [&](double phi) {
              const Vec3 k = std::cos(t) * (std::cos(phi) * n + std::sin(phi) * u) + std::sin(t) * e;
              return std::cos(t) * std::max(k.z, 0.0) * model.f(k, j);
            },
            phi_breaks);
      },
      t_breaks);
}

TEST(LawIntegrals, SharpLobesAgreeWithAnIndependentReference) {
  struct Sharp {
    std::string spec;
    bool mirror_lobe;  // lobe about the mirror of j (specular) or about j itself (backscatter)
  };
  const std::vector<Sharp> models{
      {"specular:alpha=100", true}, {"specular:alpha=1000", true}, {"backscatter:alpha=1000", false}};
  // Lobe inside the lune, at its sky edge (j's mirror perpendicular to i), and outside it.
  const std::vector<std::pair<double, double>> geometry{{60, 30}, {0, 45},     {120, 30},    {150, 60},
                                                        {91, 1},  {179.9, 80}, {45, 89.9999}};
  int cases = 0, dishonest = 0;
  for (const auto& model : models) {
    const ModelPtr m = parse_model(model.spec);
    for (auto [theta_i, theta_j] : geometry)
      for (double phi_deg : {0.0, 90.0, 180.0}) {
        const Vec3 i = direction_from_cos(std::cos(theta_i * pi / 180)),
                   j = direction_from_cos(std::cos(theta_j * pi / 180), phi_deg * pi / 180);
        const Estimate e = vignetting(*m, i, j, options());
        const double ref = reference_vignetting(*m, i, j, model.mirror_lobe ? mirror(j) : j);
        ASSERT_TRUE(e.converged) << model.spec << " " << theta_i << " " << theta_j << " " << phi_deg;
        ASSERT_TRUE(std::isfinite(e.value));
        EXPECT_NEAR(e.value, ref, kTol) << model.spec << " " << theta_i << " " << theta_j << " " << phi_deg;
        ++cases;
        if (std::abs(e.value - ref) > e.error + 1e-13) ++dishonest;
      }
  }
  EXPECT_LE(dishonest, (1.0 - kHonestFraction) * cases);
}

// ---------------------------------------------------------------------------------------------
// A sky with pole i and the complementary sky with pole -i make a Ganzfeld: g(i) + g(-i) = h.
// A closed-form-free identity that exercises the lune map for every model and geometry.
TEST(LawIntegrals, ComplementarySkiesMakeAGanzfeld) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const std::string spec : {"minnaert:xi=0.3", "specular:alpha=8", "specular:alpha=1000", "backscatter:alpha=4",
                                 "perfect-backscatter:alpha=2", "asperity:alpha=4", "asperity:alpha=1000"}) {
    const ModelPtr m = parse_model(spec);
    for (int k = 0; k < 8; ++k) {
      const Vec3 i = direction_from_cos(2 * u(rng) - 1, 2 * pi * u(rng)),
                 j = direction_from_cos(u(rng), 2 * pi * u(rng));
      const Estimate up = vignetting(*m, i, j, options()), down = vignetting(*m, -i, j, options());
      const Estimate h = darkening(*m, j, options());
      EXPECT_NEAR(up.value + down.value, h.value, up.error + down.error + h.error + 1e-14) << spec;
    }
  }
}

TEST(LawIntegrals, PoleLimits) {
  const Specular m(8);
  const Vec3 j = direction_from_cos(0.4, 1.0);
  EXPECT_EQ(vignetting(m, {0, 0, -1}, j, options()).value, 0.0);  // the sky below: nothing
  EXPECT_NEAR(vignetting(m, {0, 0, 1}, j, options()).value, darkening(m, j, options()).value, 2 * kTol);
  EXPECT_NEAR(vignetting(m, direction_from_cos(1 - 1e-15), j, options()).value, darkening(m, j, options()).value, 1e-7);
  EXPECT_LT(vignetting(m, direction_from_cos(-0.999), j, options()).value, 1e-3);
}

// ---------------------------------------------------------------------------------------------
// Extreme geometries: converged, finite, never NaN/Inf, for every law.
TEST(LawIntegrals, ConvergesAtTheExtremes) {
  const std::vector<std::string> specs{"minnaert:xi=1e-6",
                                       "minnaert:xi=0.3",
                                       "minnaert:xi=50",
                                       "specular:alpha=1000",
                                       "backscatter:alpha=1000",
                                       "perfect-backscatter:alpha=2",
                                       "perfect-backscatter:alpha=50",
                                       "asperity:alpha=1000"};
  const std::vector<double> cos_i{-1.0, -0.999, 0.0, 1e-6, 0.5, 1.0};
  const std::vector<double> cos_j{0.0, 1e-6, 0.5, 1.0};
  for (const auto& spec : specs) {
    const ModelPtr m = parse_model(spec);
    for (double ci : cos_i)
      for (double cj : cos_j)
        for (double phi : {0.0, pi / 2, pi}) {
          const Vec3 i = direction_from_cos(ci), j = direction_from_cos(cj, phi);
          for (Law law : {Law::g, Law::h, Law::a}) {
            if (law == Law::a && ci < 0) continue;
            const Estimate e = evaluate_law(*m, law, i, j, options());
            ASSERT_TRUE(std::isfinite(e.value) && std::isfinite(e.error)) << spec;
            ASSERT_TRUE(e.converged) << spec << " law " << to_string(law) << " ci=" << ci << " cj=" << cj;
            ASSERT_GE(e.value, -kTol) << spec;
          }
        }
    const Estimate r = double_diffuse(*m, options(1e-9));
    EXPECT_TRUE(r.converged && std::isfinite(r.value)) << spec;
  }
}

// Perfect backscatter near double grazing: f ~ 1/((i+j)·n), yet (k·n) f stays bounded and
// g(i) + g(-i) = h must still hold.
TEST(LawIntegrals, PerfectBackscatterNearDoubleGrazing) {
  const PerfectBackscatter m(2);
  for (double mu : {0.0, 1e-9, 1e-6, 1e-3}) {
    const Vec3 i = direction_from_cos(mu), j = direction_from_cos(mu, pi);
    const Estimate up = vignetting(m, i, j, options()), down = vignetting(m, -i, j, options());
    const Estimate h = darkening(m, j, options());
    ASSERT_TRUE(up.converged && down.converged && h.converged) << mu;
    EXPECT_NEAR(up.value + down.value, h.value, up.error + down.error + h.error + 1e-14) << mu;
  }
}

TEST(LawIntegrals, NonConvergenceIsReportedNotHidden) {
  const Specular m(1000);
  CubatureOptions tight = options(1e-15);
  tight.max_evaluations = 20000;  // above the hint grid (~9k), far below what 1e-15 needs
  const Estimate e = vignetting(m, direction_from_cos(0.5), direction_from_cos(0.8, pi), tight);
  EXPECT_FALSE(e.converged);
  EXPECT_TRUE(std::isfinite(e.value));
  EXPECT_GT(e.error, tight.abs_tol);
  EXPECT_LE(e.evaluations, tight.max_evaluations);
}

TEST(LawIntegrals, ACancelledIntegralStopsBetweenPanelsNotConverged) {
  // A sharp lobe at a tolerance it cannot meet: without the flag it runs to its whole budget.
  const Specular m(1000);
  CubatureOptions o = options(1e-15);
  o.max_evaluations = 2'000'000;
  std::atomic<bool> cancel{true};
  o.cancel = &cancel;
  const Estimate before = vignetting(m, direction_from_cos(0.5), direction_from_cos(0.8, pi), o);
  EXPECT_FALSE(before.converged);
  EXPECT_EQ(before.evaluations, 0) << "a flag set before the first panel: no panel is evaluated";

  // Set by the integrand itself after 40 panels: the engine stops before the next bisection (a
  // bisection evaluates its two halves, so at most one panel more; the box's two ends are one
  // point each).
  constexpr long long kPanelsBeforeCancel = 40, kBoxEnds = 2;
  cancel = false;
  long long panels = 0;
  const Estimate during = adaptive_cubature<1>(
      [&](const std::array<std::span<const double>, 1>& nodes, std::span<double> values) {
        for (std::size_t a = 0; a < nodes[0].size(); ++a) values[a] = std::sqrt(std::abs(nodes[0][a] - 0.3));  // kink
        if (nodes[0].size() == kRuleNodes && ++panels == kPanelsBeforeCancel) cancel = true;
      },
      {std::vector<double>{0.0, 1.0}}, o);
  EXPECT_FALSE(during.converged);
  EXPECT_GE(during.evaluations, kPanelsBeforeCancel * kRuleNodes);
  EXPECT_LE(during.evaluations, (kPanelsBeforeCancel + 1) * kRuleNodes + kBoxEnds);
  EXPECT_TRUE(std::isfinite(during.value));

  cancel = false;  // an unset flag changes nothing
  const Estimate free = vignetting(m, direction_from_cos(0.5), direction_from_cos(0.8, pi), options(1e-6));
  CubatureOptions with_flag = options(1e-6);
  with_flag.cancel = &cancel;
  const Estimate flagged = vignetting(m, direction_from_cos(0.5), direction_from_cos(0.8, pi), with_flag);
  EXPECT_EQ(free.value, flagged.value);
  EXPECT_EQ(free.evaluations, flagged.evaluations);
  EXPECT_TRUE(flagged.converged);
}

// ---------------------------------------------------------------------------------------------
// Integrands that are NaN or +Inf somewhere. Where the bad set has measure zero the integral is
// still defined and refinement must find it honestly; where it has area no value can be trusted.

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// x is a multiple of 1/n: the midpoints of the first bisections of [0, 1], which panels' centre
/// nodes hit until the refinement passes them.
bool on_grid(double x, double n) { return std::floor(n * x) == n * x; }

/// Runge's function: needs real refinement after the bad points are passed. ∫_0^1 = atan(5)/5.
double runge(double x) { return 1.0 / (1.0 + 25.0 * x * x); }
const double kRungeIntegral = std::atan(5.0) / 5.0;

TEST(LawIntegrals, NonFinitePointsAreBisectedPastIn1D) {
  const std::vector<double> unit{0.0, 1.0};
  const Estimate nan_at = adaptive_cubature<1>(pointwise<1>([](double x) { return on_grid(x, 8) ? kNaN : runge(x); }),
                                               {unit}, options(1e-12));
  const Estimate inf_at = adaptive_cubature<1>(pointwise<1>([](double x) { return on_grid(x, 8) ? kInf : runge(x); }),
                                               {unit}, options(1e-12));
  for (const Estimate& e : {nan_at, inf_at}) {
    EXPECT_TRUE(e.converged);
    EXPECT_LE(e.error, 1e-12);
    EXPECT_LE(std::abs(e.value - kRungeIntegral), e.error + 1e-15) << "dishonest estimate";
  }
}

TEST(LawIntegrals, NonFinitePointsAndLinesAreBisectedPastIn2D) {
  const std::vector<double> unit{0.0, 1.0};
  // NaN on the lines x = k/4 and y = k/4 (a line in y is only passed by bisecting y), +Inf on
  // the points (k/8, l/8).
  const Estimate nan_on = adaptive_cubature<2>(
      pointwise<2>([](double x, double y) { return on_grid(x, 4) || on_grid(y, 4) ? kNaN : runge(x) * runge(y); }),
      {unit, unit}, options(1e-12));
  const Estimate inf_at = adaptive_cubature<2>(
      pointwise<2>([](double x, double y) { return on_grid(x, 8) && on_grid(y, 8) ? kInf : runge(x) * runge(y); }),
      {unit, unit}, options(1e-12));
  for (const Estimate& e : {nan_on, inf_at}) {
    EXPECT_TRUE(e.converged);
    EXPECT_LE(e.error, 1e-12);
    EXPECT_LE(std::abs(e.value - kRungeIntegral * kRungeIntegral), e.error + 1e-15) << "dishonest estimate";
  }
}

TEST(LawIntegrals, NonFiniteRegionsAreReportedNotConverged) {
  const std::vector<double> unit{0.0, 1.0};
  CubatureOptions o = options(1e-12);
  o.max_evaluations = 1'000'000;
  const Estimate nan_1d =
      adaptive_cubature<1>(pointwise<1>([](double x) { return x > 0.25 && x < 0.5 ? kNaN : 1.0; }), {unit}, o);
  const Estimate inf_1d =
      adaptive_cubature<1>(pointwise<1>([](double x) { return x > 0.25 && x < 0.5 ? kInf : 1.0; }), {unit}, o);
  const Estimate nan_2d = adaptive_cubature<2>(
      pointwise<2>([](double x, double y) { return x > 0.2 && x < 0.3 && y > 0.6 && y < 0.7 ? kNaN : x * y; }),
      {unit, unit}, o);
  for (const Estimate& e : {nan_1d, inf_1d, nan_2d}) {
    EXPECT_FALSE(e.converged);
    EXPECT_EQ(e.error, kInf);  // not NaN: an error estimate stays comparable
    EXPECT_TRUE(std::isfinite(e.value));
    // Given up at the resolution limit of doubles, not by spending the budget.
    EXPECT_LT(e.evaluations, o.max_evaluations / 10);
  }
}

// ---------------------------------------------------------------------------------------------
// The estimate without hints: integrands from Genz's test families (bench/genz_bench.h) on the
// box's ends alone, each a case the raw |K - G| estimate (before null rules, halves and sides)
// called converged while off by more than it said (listed with that ratio).

/// Relative tolerances every pinned case is run at.
const std::vector<double> kRelativeTolerances{1e-3, 1e-6, 1e-9, 1e-12};
/// Rounding allowed on top of the estimate: 50 ulps of the integral (the engine's own floor).
constexpr double kRoundingUlps = 50.0;

/// ∫_0^1 of one factor of Genz's C0, Gaussian and discontinuous integrands.
double c0_factor(double a, double u) { return (-std::expm1(-a * u) - std::expm1(-a * (1.0 - u))) / a; }
double gaussian_factor(double a, double u) {
  return std::sqrt(pi) / (2.0 * a) * (std::erf(a * (1.0 - u)) + std::erf(a * u));
}
double step_factor(double a, double u) { return std::expm1(a * u) / a; }

template <int D, class F>
void expect_honest_without_hints(F f, double exact, const std::string& label) {
  for (double tolerance : kRelativeTolerances) {
    CubatureOptions o = options(tolerance * std::abs(exact));
    o.max_evaluations = 5'000'000;
    std::array<std::vector<double>, D> box;
    box.fill({0.0, 1.0});
    Estimate e;
    if constexpr (D == 1) e = adaptive_cubature<1>(pointwise<1>(f), box, o);
    else e = adaptive_cubature<2>(pointwise<2>(f), box, o);
    EXPECT_LE(std::abs(e.value - exact),
              e.error + kRoundingUlps * std::numeric_limits<double>::epsilon() * std::abs(exact))
        << label << " at relative tolerance " << tolerance << ": " << e.value << " ± " << e.error << ", exact " << exact
        << (e.converged ? "" : " (not converged)");
  }
}

TEST(EstimateWithoutHints, NullRulesBoundKinksAndJumpsInOnePanel) {
  // One panel, no bisection: wherever a kink or a jump lies between its outermost nodes, the
  // estimate bounds K15's error (raw |K - G| vanishes for some positions: 10^3x and more).
  CubatureOptions single = options(1e-300);
  single.max_evaluations = kRuleNodes;
  single.bisect_initial_panels = false;
  constexpr int kPositions = 4000;
  const double outermost = 0.99145537112081263920685469752598;  // the K15 node next to ±1
  const std::array<std::vector<double>, 1> panel{std::vector<double>{-1.0, 1.0}};
  for (int k = 1; k < kPositions; ++k) {
    const double u = -outermost + 2.0 * outermost * k / kPositions;
    const Estimate kink = adaptive_cubature<1>(pointwise<1>([u](double x) { return std::abs(x - u); }), panel, single);
    const Estimate jump =
        adaptive_cubature<1>(pointwise<1>([u](double x) { return x > u ? 1.0 : 0.0; }), panel, single);
    const double kink_exact = 0.5 * ((1 - u) * (1 - u) + (1 + u) * (1 + u)), jump_exact = 1.0 - u;
    ASSERT_LE(std::abs(kink.value - kink_exact), kink.error) << "kink at " << u;
    ASSERT_LE(std::abs(jump.value - jump_exact), jump.error) << "jump at " << u;
  }
}

TEST(EstimateWithoutHints, GaussianPeakBetweenTheNodesOfTheFirstPanel) {
  // Genz's Gaussian in 1-D at his difficulty (a = 100): 0.0177 missed, 1.1e-9 estimated (1.6e7x).
  const double a = 100.0, u = 0.33981333708360878;
  expect_honest_without_hints<1>([=](double x) { return std::exp(-a * a * (x - u) * (x - u)); }, gaussian_factor(a, u),
                                 "gaussian");
}

TEST(EstimateWithoutHints, KinkInTheGapNextToACut) {
  // Genz's C0 in 1-D (a = 150): the kink lies between a cut and its halves' outermost nodes
  // (161x at 1e-12).
  const double a = 150.0, u = 0.8924552022496044;
  expect_honest_without_hints<1>([=](double x) { return std::exp(-a * std::abs(x - u)); }, c0_factor(a, u), "c0 1-D");
}

TEST(EstimateWithoutHints, KinksIn2D) {
  // Genz's C0 in 2-D: 19.5x at 1e-3.
  const double a0 = 18.694987033009635, a1 = 18.805012966990361, u0 = 0.95491238984623206, u1 = 0.18433001253834477;
  expect_honest_without_hints<2>(
      [=](double x, double y) { return std::exp(-a0 * std::abs(x - u0) - a1 * std::abs(y - u1)); },
      c0_factor(a0, u0) * c0_factor(a1, u1), "c0 2-D");
}

TEST(EstimateWithoutHints, KinkInTheGapNextToTheBoxEnd) {
  // Genz's C0 in 2-D with a kink 0.0015 from the box's end x = 1 (1640x at 1e-6), and one
  // 0.0024 from y = 0 (4160x at 1e-9): between the outermost nodes and the box's side, seen
  // only by the line evaluated on that side.
  const double a0 = 18.921071609841832, a1 = 18.578928390158172, u0 = 0.9984958156310515, u1 = 0.028609210509137992;
  expect_honest_without_hints<2>(
      [=](double x, double y) { return std::exp(-a0 * std::abs(x - u0) - a1 * std::abs(y - u1)); },
      c0_factor(a0, u0) * c0_factor(a1, u1), "c0 2-D, kink next to x = 1");
  const double b0 = 30.243356731772987, b1 = 7.256643268227009, v0 = 0.64651525785604691, v1 = 0.0023624814974124858;
  expect_honest_without_hints<2>(
      [=](double x, double y) { return std::exp(-b0 * std::abs(x - v0) - b1 * std::abs(y - v1)); },
      c0_factor(b0, v0) * c0_factor(b1, v1), "c0 2-D, kink next to y = 0");
}

TEST(EstimateWithoutHints, JumpSeenByTheNodes) {
  // Genz's discontinuous family in 1-D (a = 100): 1e6x at 1e-3.
  const double a = 100.0, u = 0.22070882066469488;
  expect_honest_without_hints<1>([=](double x) { return x > u ? 0.0 : std::exp(a * x); }, step_factor(a, u),
                                 "discontinuous");
}

TEST(EstimateWithoutHints, JumpsInTheGapsOfACorner) {
  // Genz's discontinuous family in 2-D (29x at 1e-12): a strip below the jump y = u1 hid in the
  // gap next to a cut, and the jump x = u0 in the gap next to the panels' other side, which an
  // ancestor had settled while its nodes all lay where the integrand is 0.
  const double a0 = 17.932526565690225, a1 = 7.0674734343097745, u0 = 0.38573984327978755, u1 = 0.32720955811326885;
  expect_honest_without_hints<2>([=](double x, double y) { return x > u0 || y > u1 ? 0.0 : std::exp(a0 * x + a1 * y); },
                                 step_factor(a0, u0) * step_factor(a1, u1), "discontinuous 2-D");
}

TEST(EstimateWithoutHints, ProductPeakIn2D) {
  // Genz's product peak in 2-D: 35x at 1e-3.
  const double a0 = 44.519019105311337, a1 = 105.48098089468867, u0 = 0.34575263373924253, u1 = 0.5660047561260122;
  auto factor = [](double a, double u) { return a * (std::atan(a * (1.0 - u)) + std::atan(a * u)); };
  expect_honest_without_hints<2>(
      [=](double x, double y) {
        return 1.0 / ((1.0 / (a0 * a0) + (x - u0) * (x - u0)) * (1.0 / (a1 * a1) + (y - u1) * (y - u1)));
      },
      factor(a0, u0) * factor(a1, u1), "product peak");
}

TEST(EstimateWithoutHints, BadToleranceOrBudgetIsRefused) {
  const std::vector<double> unit{0.0, 1.0};
  const auto one = pointwise<1>([](double x) { return x; });
  const auto two = pointwise<2>([](double x, double y) { return x * y; });
  for (double tol : {0.0, -1e-9, kNaN, kInf, 1e-320}) {
    CubatureOptions o = options(tol);
    EXPECT_THROW(adaptive_cubature<1>(one, {unit}, o), InputError) << tol;
    EXPECT_THROW(adaptive_cubature<2>(two, {unit, unit}, o), InputError) << tol;
  }
  CubatureOptions small = options(1e-9);
  small.max_evaluations = kRuleNodes - 1;
  EXPECT_THROW(adaptive_cubature<1>(one, {unit}, small), InputError);
  small.max_evaluations = kRuleNodes * kRuleNodes - 1;
  EXPECT_THROW(adaptive_cubature<2>(two, {unit, unit}, small), InputError);
  small.max_evaluations = kRuleNodes;  // one panel is enough in 1-D
  EXPECT_NO_THROW(adaptive_cubature<1>(one, {unit}, small));
}

// Same input, same bits: sequential, one thread and two threads.
TEST(LawIntegrals, DeterministicWhateverTheThreadCount) {
  const ModelPtr m = parse_model("0.7*minnaert:xi=0.3 + 0.3*specular:alpha=300");
  std::vector<std::pair<Vec3, Vec3>> points;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 64; ++k)
    points.push_back({direction_from_cos(2 * u(rng) - 1, 0), direction_from_cos(u(rng), pi * u(rng))});
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<double> out(points.size());
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t k) {
      out[k] = vignetting(*m, points[k].first, points[k].second, options()).value;
    });
    out.push_back(double_diffuse(*m, options()).value);
    return out;
  };
  const auto one = run(1), two = run(2);
  for (std::size_t k = 0; k < one.size(); ++k) EXPECT_EQ(one[k], two[k]) << k;  // bitwise
}

// ---------------------------------------------------------------------------------------------
// Creased integrands (MassHints::crease_axis): a BRDF that jumps across great circles through
// the x axis, as Poulin–Fournier's cylinder shadowing does, integrated exactly by the crease
// frame. The reference is independent of the cubature: Lambert's formula for the cosine-
// weighted solid angle of a spherical polygon, ∫ (k·n) dk = n · (1/2) Σ θ_e u_e over its edges.

/// f(i, j) = w(i) w(j) with w = A where the longitude about x is below `crease`, B above.
class CreasedStep final : public Model {
 public:
  CreasedStep(double crease, double below, double above, bool hinted)
      : crease_(crease), below_(below), above_(above), hinted_(hinted) {}
  static double longitude(const Vec3& k) { return std::atan2(-k.y, k.z); }  // u = x × n = -y
  double w(const Vec3& k) const { return longitude(k) < crease_ ? below_ : above_; }
  std::string spec() const override { return "creased-step"; }
  Traits traits() const override { return {false, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override { return i.z < 0.0 || j.z < 0.0 ? 0.0 : w(i) * w(j); }
  MassHints mass_hints(const Vec3&, Varying) const override {
    HintBuilder h;
    if (hinted_) h.creases({1.0, 0.0, 0.0}, {crease_});
    return h.build();
  }

 private:
  double crease_, below_, above_;
  bool hinted_;
};

/// ∫ (k·n) dk over {k·a >= 0} ∩ {k·b >= 0} ∩ {k·c >= 0} (unit a, b, c in general position):
/// the region's boundary runs along each great circle u·k = 0 (u = a, b, c) for the arc that
/// meets the other two constraints, an intersection of two half circles; each edge adds
/// (arc angle) u / 2 to ∫ k dk (Lambert's formula; a lune's two half circles give (pi/2)(a + b)).
double cosine_over_region(const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::array<Vec3, 3> planes{a, b, c};
  Vec3 sum{0.0};
  for (int e = 0; e < 3; ++e) {
    const Vec3& u = planes[e];
    const Vec3 x = glm::normalize(glm::cross(u, std::abs(u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 y = glm::cross(u, x);
    // On the circle k = cos s x + sin s y, constraint v keeps the half circle centred at atan2(y·v, x·v).
    double centre[2];
    for (int o = 0; o < 2; ++o) {
      const Vec3& v = planes[(e + 1 + o) % 3];
      centre[o] = std::atan2(glm::dot(y, v), glm::dot(x, v));
    }
    double gap = std::abs(centre[0] - centre[1]);
    if (gap > pi) gap = 2 * pi - gap;
    sum += 0.5 * std::max(0.0, pi - gap) * u;
  }
  return sum.z;
}

TEST(LawIntegrals, CreasedIntegrandsAreSplitAtTheirCreasesAndExact) {
  constexpr double kCreaseTol = 1e-11;   // requested; the jumps must cost nothing in accuracy
  constexpr double kBudget = 2'000'000;  // evaluations: ample for a piecewise-constant integrand
  constexpr double kBelow = 0.1, kAbove = 0.3;
  const Vec3 n{0, 0, 1};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 60; ++k) {
    const double crease = (u(rng) - 0.5) * 0.98 * pi;
    const CreasedStep model(crease, kBelow, kAbove, true);
    // The crease's half-space {longitude < crease} within the hemisphere is {k·q >= 0}.
    const Vec3 q{0.0, std::cos(crease), std::sin(crease)};
    // Sky poles: generic, below the horizon, perpendicular to the crease axis, near it.
    Vec3 pole = direction_from_cos(2 * u(rng) - 1, 2 * pi * u(rng));
    if (k % 4 == 1) pole = glm::normalize(Vec3{0.0, pole.y, pole.z});
    if (k % 4 == 2) pole = glm::normalize(Vec3{1e-7 * (u(rng) - 0.5), pole.y, pole.z});
    const Vec3 j = direction_from_cos(u(rng), 2 * pi * u(rng));
    CubatureOptions o = options(kCreaseTol);
    o.max_evaluations = kBudget;
    // g: lune of the pole, split by the crease.
    const double lune_total = pi * (1.0 + pole.z) / 2.0;
    const double below = cosine_over_region(n, pole, q);
    const double exact_g = model.w(j) * (kBelow * below + kAbove * (lune_total - below));
    const Estimate g = vignetting(model, pole, j, o);
    EXPECT_TRUE(g.converged) << "crease " << crease << " pole " << pole.x << "," << pole.y << "," << pole.z;
    EXPECT_NEAR(g.value, exact_g, kCreaseTol) << "crease " << crease;
    EXPECT_LE(std::abs(g.value - exact_g), g.error + 1e-15) << "dishonest estimate, crease " << crease;
    // h and a: the hemisphere, split by the crease: (pi/2)(1 + sin crease) lies below it.
    const double half_below = pi / 2 * (1.0 + std::sin(crease));
    const double exact_h = model.w(j) * (kBelow * half_below + kAbove * (pi - half_below));
    const Estimate h = darkening(model, j, o);
    const Estimate a = albedo(model, j, o);
    EXPECT_NEAR(h.value, exact_h, kCreaseTol);
    EXPECT_NEAR(a.value, exact_h, kCreaseTol);
    EXPECT_TRUE(h.converged && a.converged);
  }
  // Without the hint the same jump is bisected towards forever: the budget runs out first.
  const CreasedStep unhinted(0.3, kBelow, kAbove, false);
  CubatureOptions o = options(kCreaseTol);
  o.max_evaluations = kBudget;
  EXPECT_FALSE(vignetting(unhinted, direction_from_cos(0.4, 1.0), direction_from_cos(0.5, 2.0), o).converged);
}

}  // namespace
}  // namespace ganzfeld
