// Genz's test families (bench/genz_bench.h): the closed forms against a quadrature written apart
// (Boost's gauss_kronrod, split at every kink and jump), the lines the "unseen" verdict watches,
// and the refusals of bad options.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "bench/genz_bench.h"
#include "util/error.h"

namespace ganzfeld::bench {
namespace {

/// The closed forms are long double; Boost's adaptive rule is asked for 1e-12 relative on smooth
/// pieces, so they must agree to 10x that.
constexpr double kClosedFormTolerance = 1e-11;

/// ∫ over [0,1]^n by nested gauss_kronrod<61>, each axis split at the instance's u (where C0 bends
/// and the discontinuous family jumps; elsewhere a harmless extra cut).
double numerical(const GenzInstance& in) {
  using Rule = boost::math::quadrature::gauss_kronrod<double, 61>;
  auto split = [](auto f, double u) {
    return Rule::integrate(f, 0.0, u, 12, 1e-12) + Rule::integrate(f, u, 1.0, 12, 1e-12);
  };
  if (in.dimension == 1) return split([&](double x) { return in(&x); }, in.u[0]);
  return split(
      [&](double x) {
        return split(
            [&](double y) {
              const double p[2] = {x, y};
              return in(p);
            },
            in.u[1]);
      },
      in.u[0]);
}

TEST(GenzBench, ClosedFormsMatchAQuadratureWrittenApart) {
  std::mt19937_64 rng(7);
  for (int dimension : {1, 2})
    for (GenzFamily family : kGenzFamilies)
      for (int k = 0; k < 2; ++k) {
        const GenzInstance in = make_genz_instance(family, dimension, rng);
        const double exact = static_cast<double>(in.exact), q = numerical(in);
        EXPECT_NEAR(q, exact, kClosedFormTolerance * in.l1_norm())
            << to_string(family) << " " << dimension << "-D, a = " << in.a[0] << ", " << in.a[1] << ", u = " << in.u[0]
            << ", " << in.u[1];
      }
}

TEST(GenzBench, DifficultyIsGenzs) {
  std::mt19937_64 rng(3);
  // Σ aᵢ = 110/n^1.5 (oscillatory), 100/n (Gaussian), 150/n² (C0).
  EXPECT_NEAR(make_genz_instance(GenzFamily::oscillatory, 1, rng).a[0], 110.0, 1e-12);
  const GenzInstance gaussian = make_genz_instance(GenzFamily::gaussian, 2, rng);
  EXPECT_NEAR(gaussian.a[0] + gaussian.a[1], 50.0, 1e-12);
  const GenzInstance c0 = make_genz_instance(GenzFamily::c0, 2, rng);
  EXPECT_NEAR(c0.a[0] + c0.a[1], 37.5, 1e-12);
}

TEST(GenzBench, SingularLinesAreWhereTheIntegrandBendsOrJumps) {
  std::mt19937_64 rng(5);
  EXPECT_TRUE(singular_lines(make_genz_instance(GenzFamily::gaussian, 2, rng)).empty());
  const GenzInstance c0 = make_genz_instance(GenzFamily::c0, 2, rng);
  const auto kinks = singular_lines(c0);
  ASSERT_EQ(kinks.size(), 2u);
  EXPECT_EQ(kinks[0].at, c0.u[0]);
  EXPECT_EQ(kinks[0].extent, 1.0);
  // The discontinuous integrand jumps on x = u₀ only where y < u₁ (beyond, it is 0 on both sides).
  const GenzInstance jump = make_genz_instance(GenzFamily::discontinuous, 2, rng);
  const auto jumps = singular_lines(jump);
  ASSERT_EQ(jumps.size(), 2u);
  EXPECT_EQ(jumps[0].axis, 0);
  EXPECT_EQ(jumps[0].extent, jump.u[1]);
}

TEST(GenzBench, BadOptionsAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double t : {0.0, -1e-6, nan, 1e-15, 1.0}) {
    GenzOptions o = quick_genz_options();
    o.tolerances = {t};
    EXPECT_THROW(check_genz_options(o), InputError) << t;
  }
  GenzOptions budget = quick_genz_options();
  budget.budget = 224;  // below one 15 x 15 panel in 2-D
  EXPECT_THROW(check_genz_options(budget), InputError);
  budget.dimensions = {1};
  EXPECT_NO_THROW(check_genz_options(budget));
  GenzOptions none = quick_genz_options();
  none.instances = 0;
  EXPECT_THROW(check_genz_options(none), InputError);
}

TEST(GenzBench, DishonestOnlyWhenClaimedAndBeyondTheEstimate) {
  GenzRun run;
  run.error = 2e-9;
  run.estimate = 1e-9;
  run.resolution = 1e-15;
  EXPECT_FALSE(run.dishonest());  // not claimed: a run that says it did not converge is not lying
  run.claimed = true;
  EXPECT_TRUE(run.dishonest());
  run.estimate = 2e-9 - 0.5e-15;  // within the resolution
  EXPECT_FALSE(run.dishonest());
}

TEST(GenzBench, TheSampleIsMetOnlyAtEveryToleranceOfTheTarget) {
  // The verdict on the sample: every default tolerance (1e-3, 1e-4, ..., 1e-12) and >= 500
  // instances; the range's two ends alone are not the sample.
  const std::string line = "instances per family and dimension, each at every relative tolerance";
  auto sample_verdict = [&](const GenzOptions& options) {
    const std::string md = genz_markdown({}, options, "test", 0.0);
    const std::size_t at = md.find(line);
    EXPECT_NE(at, std::string::npos);
    return md.substr(at, md.find('\n', at) - at);
  };
  GenzOptions full;
  EXPECT_NE(sample_verdict(full).find("**met** (500 instances; 10 of the 10 tolerances"), std::string::npos)
      << sample_verdict(full);
  GenzOptions ends = full;
  ends.tolerances = {1e-3, 1e-12};
  EXPECT_NE(sample_verdict(ends).find("**missed** (500 instances; 2 of the 10 tolerances"), std::string::npos)
      << sample_verdict(ends);
  GenzOptions small = full;
  small.instances = 499;
  EXPECT_NE(sample_verdict(small).find("**missed**"), std::string::npos) << sample_verdict(small);
}

}  // namespace
}  // namespace ganzfeld::bench
