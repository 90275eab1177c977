// `ganzfeld bench cubature`: work–precision of our engine against what a user would pick
// instead, on the same integrands (the law of vignetting over the lune), in one run.
//
// Every competitor sees the integrand through one counting wrapper with an evaluation cap:
//   ours                 integrate/ (tensor G7/K15, global adaptivity, hint cuts); its evaluations
//                        are counted by a Model wrapper around f, not taken from its own report
//   ours_no_hints        the same engine with the model's mass hints hidden: what it does with the
//                        information the peers get (the integrand alone)
//   hcubature_lune       S. G. Johnson's hcubature on the same lune rectangle
//   pcubature_lune       its p-adaptive Clenshaw–Curtis cousin, same rectangle
//   hcubature_naive      hcubature on the hemisphere (theta, phi) with an indicator k·i > 0
//   boost_gauss_kronrod  Boost.Math adaptive gauss_kronrod<15>, nested, on the lune rectangle
//   boost_tanh_sinh      Boost.Math tanh_sinh, nested, on the lune rectangle
//   mc                   Monte Carlo with cosine-weighted sampling, given our wall time
//   oracle               a *uniform* composite Gauss–Legendre rule on our initial grid (our cuts),
//                        n chosen in hindsight as the smallest that reaches the target: the
//                        cheapest uniform rule on our cuts, not a lower bound for adaptive rules
// All get the same absolute tolerances and the same evaluation cap (ours through
// CubatureOptions::max_evaluations).
// The reference of every case is independent of integrate/: Boost gauss_kronrod<61>, nested, with
// break points at the lobe (bench/, written apart from the engine). Ours at 1e-13 is computed
// too; where the two differ by more than kReferenceAgreement the case is *kept* and listed
// (FamilyResult::disagreements). Every verdict (judge()) compares the unfloored achieved error
// with the tolerance or the run's estimate plus the case's resolution (Reference::resolution():
// Boost's stated error + |ref1 - ref2| + kRoundingUlps of |ref|).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace ganzfeld::bench {

using Vec3Triple = std::array<double, 3>;  // a direction, without pulling GLM into this header

inline constexpr double kReferenceAgreement = 1e-12;
/// Rounding no double-precision cubature resolves on an integral of L1 norm `scale`: 50 ulps of
/// it, the allowance the engine makes for its own sums (integrate/cubature.cpp, the panel's
/// rounding term) granted to the reference's sums too. The benchmark's integrands are
/// nonnegative ((k·n) f(k, j) cos t, f a BRDF), so their L1 norm is |reference|.
inline constexpr double kRoundingUlps = 50.0;

/// A case's reference: the independent value (Boost GK61, reference/), the doubt about it (its
/// difference from ours at 1e-13) and its own stated error (Boost's estimates, outer + inner).
struct Reference {
  double value = 0.0, doubt = 0.0, error = 0.0;
  /// What an achieved error is measured to on this case: the reference's stated error plus the
  /// doubt plus kRoundingUlps of |value|. An error below it is not resolved; a verdict never
  /// blames a run for less.
  double resolution() const;
};

struct CubatureBenchOptions {
  int cases_per_family = 200;
  std::vector<double> tolerances{1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
  double ratio_tolerance = 1e-10;        ///< the requested tolerance at which ratios are reported
  long long competitor_cap = 2'000'000;  ///< evaluations per competitor run
  unsigned seed = 20190117;
  /// Only these competitors (names as in the tables: ours, ours_no_hints, oracle, mc, ...); empty:
  /// all. Ratios need ours; the references are computed either way.
  std::vector<std::string> competitors{};
  bool runs(const std::string& competitor) const;
};
/// The competitors' names, as --competitors takes them.
const std::vector<std::string>& cubature_competitors();
CubatureBenchOptions quick_options();

struct Run {  // one competitor at one requested tolerance on one case
  std::string competitor;
  /// achieved_error = |value - reference| exactly, no floor; resolution = Reference::resolution()
  double tolerance = 0.0, achieved_error = 0.0, estimate = 0.0, seconds = 0.0, resolution = 0.0;
  long long evaluations = 0;
  bool capped = false;
  bool claimed = false;  ///< the competitor says it met the tolerance (converged, estimate <= tol)
};

/// A run's value measured against the case's reference (no floor on the error).
Run measured(const std::string& competitor, double value, double estimate, double tolerance,
             const Reference& reference);

/// The verdicts on one run, each beyond the case's resolution: missed = the achieved error
/// exceeds the requested tolerance; dishonest = it exceeds the run's own error estimate. So an
/// answer exact to rounding on a value of about 0 is neither, whatever tiny estimate it states.
struct Verdict {
  bool missed = false, dishonest = false;
};
Verdict judge(const Run& run);

/// How a competitor's runs failed, counted over all requested tolerances of a family's cases.
struct Failures {
  int runs = 0;
  int silently_wrong = 0;  ///< claimed the tolerance but missed it (beyond the references' doubt)
  int not_converged = 0;   ///< said it did not meet the tolerance, within the cap
  int over_cap = 0;        ///< stopped by the evaluation cap
  int missed = 0;          ///< judge(): error above the tolerance, whatever the run claimed
  int dishonest = 0;       ///< judge(): error above the run's own estimate (runs that state one)
};

/// A case whose two references differ by more than kReferenceAgreement: kept, and shown.
struct Disagreement {
  std::string model;
  Vec3Triple i{}, j{};
  double boost_reference = 0.0, ours_reference = 0.0;
};

/// One of our runs that missed its requested tolerance or whose estimate fell below the actual
/// error: the case, so that it can be reproduced with `ganzfeld eval`.
struct Miss {
  std::string model;
  Vec3Triple i{}, j{};
  double tolerance = 0.0, achieved_error = 0.0, estimate = 0.0, resolution = 0.0;
  long long evaluations = 0;
  /// How far the error exceeds what the run promised, min(tolerance, estimate), plus resolution.
  double excess() const;
};

struct FamilyResult {
  std::string name;
  int cases = 0, skipped = 0;
  double missed_rate = 0.0;                   ///< fraction of our runs (all tolerances) missing the tolerance
  double dishonest_rate = 0.0;                ///< fraction of our runs whose estimate < actual error
  std::map<std::string, double> evals_ratio;  ///< geometric mean over cases, at ratio_tolerance
  std::map<std::string, int> capped;          ///< cases where the competitor hit the cap (ratio is a lower bound)
  double mc_error_ratio_equal_time = 0.0;     ///< geometric mean of MC error / our error (ours taken
                                              ///< as at least the case's resolution: below it, it is not
                                              ///< measured); cases where both are exact are left out
  std::map<std::string, Failures> failures;   ///< per competitor (ours included)
  std::vector<Disagreement> disagreements;
  std::vector<Run> runs;     ///< every run, for the work–precision plot
  std::vector<Miss> misses;  ///< our missed or dishonest runs
};

std::vector<FamilyResult> run_cubature_benchmark(const CubatureBenchOptions& options);

/// docs/performance.md: the ratio table per family, the targets as measured, and
/// the plot, stamped with `command`.
/// Bake throughput, repeated: a 64x64x32 g table at 1e-9 per model, with 1 and 2 threads.
struct BakeTiming {
  std::string model;
  std::vector<int> resolution;
  std::vector<double> seconds_1, seconds_2;  ///< every run
  long long unconverged = 0;
  double max_error = 0.0;
};
std::vector<BakeTiming> run_bake_benchmark(bool quick, int repeats);

/// Today's date in UTC, YYYY-MM-DD (the stamp of a generated section).
std::string today_utc();
/// x with `digits` significant digits (%g): the benchmarks' Markdown numbers.
std::string significant(double x, int digits = 3);
/// part/whole as a percentage with two significant digits, "—" when whole is 0.
std::string percent(int part, int whole);

/// Our evaluations per family in a run of the previous engine: `family,competitor,runs,evaluations`
/// lines (ours and ours_no_hints summed over every case and tolerance) after `#` comment lines that
/// say how they were made (scripts/performance-baseline). Throws InputError for a malformed file.
struct EvaluationBaseline {
  std::string source;  ///< the file's comment lines, joined
  std::map<std::string, std::map<std::string, std::pair<long long, long long>>>
      totals;  ///< family → competitor → (runs, evaluations)
};
EvaluationBaseline read_evaluation_baseline(const std::string& path);

std::string performance_markdown(const std::vector<FamilyResult>& families, const CubatureBenchOptions& options,
                                 const std::vector<BakeTiming>& bakes, const std::string& command,
                                 const std::string& plot_file, const EvaluationBaseline* baseline = nullptr);

/// Work–precision plot: per competitor and requested tolerance, the geometric means over all
/// cases of evaluations (x) and achieved error (y), joined across tolerances.
void write_work_precision_plot(const std::vector<FamilyResult>& families, const std::string& path);

}  // namespace ganzfeld::bench
