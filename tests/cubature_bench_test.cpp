// The benchmark's verdicts (bench/cubature_bench.h): an answer exact to rounding is never called
// missed or dishonest, a real undershoot always is, and the achieved error is measured unfloored.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "bench/cubature_bench.h"

namespace ganzfeld::bench {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// A value of the size of the benchmark's typical g (0.3) and an engine error two orders above
/// the case's rounding resolution (50 ulps of 0.3 = 3.3e-15): a real error, not rounding.
constexpr double kValue = 0.3, kRealError = 1e-12;

TEST(CubatureBenchVerdict, ExactToRoundingOnZeroValueIsNotDishonest) {
  // The artifact of the old benchmark: value and reference 0 (no sky at the lobe), a tiny stated
  // estimate; an error floored at 1e-16 called this dishonest.
  const auto run = measured("ours", 0.0, 7e-35, 1e-12, Reference{0.0, 0.0});
  EXPECT_EQ(run.achieved_error, 0.0);
  const Verdict v = judge(run);
  EXPECT_FALSE(v.missed);
  EXPECT_FALSE(v.dishonest);
}

TEST(CubatureBenchVerdict, TinyValueIsMeasuredUnfloored) {
  // A value of about 1e-30 off by one ulp of it, with an estimate of 1e-40: the error (~1e-46)
  // is what it is, below the estimate, so not dishonest.
  const double reference = 1e-30;
  const auto run = measured("ours", std::nextafter(reference, 1.0), 1e-40, 1e-12, Reference{reference, 0.0});
  EXPECT_GT(run.achieved_error, 0.0);
  EXPECT_LT(run.achieved_error, 1e-45);
  EXPECT_FALSE(judge(run).dishonest);
}

TEST(CubatureBenchVerdict, RoundingBelowTheResolutionIsNotDishonest) {
  // A few ulps off on 0.3, while the run states an estimate below one ulp: rounding, not a lie.
  const double value = kValue + 4 * kEpsilon * kValue;
  const auto run = measured("ours", value, 1e-18, 1e-12, Reference{kValue, 0.0});
  EXPECT_GT(run.achieved_error, run.estimate);
  EXPECT_FALSE(judge(run).dishonest);
}

TEST(CubatureBenchVerdict, RealUndershootIsDishonest) {
  // Off by 1e-12 with an estimate of 7e-13: the estimate undershoots by 30% (as the cook-torrance
  // case of independent_reference_test), met the tolerance 1e-10 but not its own word.
  const auto run = measured("ours", kValue + kRealError, 0.7 * kRealError, 1e-10, Reference{kValue, 0.0});
  const Verdict v = judge(run);
  EXPECT_TRUE(v.dishonest);
  EXPECT_FALSE(v.missed);
}

TEST(CubatureBenchVerdict, ErrorAboveTheToleranceIsMissed) {
  const auto run = measured("ours", kValue - 2 * kRealError, 3 * kRealError, kRealError, Reference{kValue, 0.0});
  const Verdict v = judge(run);
  EXPECT_TRUE(v.missed);
  EXPECT_FALSE(v.dishonest);
}

TEST(CubatureBenchVerdict, ReferencesDoubtIsNotBlamed) {
  // The same miss, on a case whose references differ by more than the miss: not a verdict.
  const auto run =
      measured("ours", kValue - 2 * kRealError, 0.5 * kRealError, kRealError, Reference{kValue, 5 * kRealError});
  const Verdict v = judge(run);
  EXPECT_FALSE(v.missed);
  EXPECT_FALSE(v.dishonest);
}

TEST(CubatureBenchVerdict, ReferencesOwnErrorIsNotBlamed) {
  // The same miss, on a case whose reference states an error larger than the miss.
  const auto run =
      measured("ours", kValue - 2 * kRealError, 0.5 * kRealError, kRealError, Reference{kValue, 0.0, 5 * kRealError});
  const Verdict v = judge(run);
  EXPECT_FALSE(v.missed);
  EXPECT_FALSE(v.dishonest);
}

TEST(CubatureBenchVerdict, NoValueIsMissedButNotDishonest) {
  // A capped run returns no value: infinite error and estimate (bench: run_boost).
  const double inf = std::numeric_limits<double>::infinity();
  const Verdict v = judge(measured("boost_gauss_kronrod", inf, inf, 1e-10, Reference{kValue, 0.0}));
  EXPECT_TRUE(v.missed);
  EXPECT_FALSE(v.dishonest);
}

}  // namespace
}  // namespace ganzfeld::bench
