// `ganzfeld bench cubature`: work–precision of our engine against what a user would pick
// instead, on the same integrands (the law of vignetting over the lune), in one run.
//
// Every competitor sees the integrand through one counting wrapper with an evaluation cap:
//   ours                 integrate/ (tensor G7/K15, global adaptivity, hint cuts)
//   hcubature_lune       S. G. Johnson's hcubature on the same lune rectangle
//   pcubature_lune       its p-adaptive Clenshaw–Curtis cousin, same rectangle
//   hcubature_naive      hcubature on the hemisphere (theta, phi) with an indicator k·i > 0
//   boost_gauss_kronrod  Boost.Math adaptive gauss_kronrod<15>, nested, on the lune rectangle
//   boost_tanh_sinh      Boost.Math tanh_sinh, nested, on the lune rectangle
//   mc                   Monte Carlo with cosine-weighted sampling, given our wall time
//   oracle               composite Gauss–Legendre on our initial grid, n chosen in hindsight as
//                        the smallest that reaches our achieved error (a lower bound)
// References: ours at 1e-13 and an independent Boost gauss_kronrod<61> nested integral; a case
// whose two references disagree by more than kReferenceAgreement is reported and skipped.
#pragma once

#include <map>
#include <string>
#include <array>
#include <vector>

namespace ganzfeld::bench {

using Vec3Triple = std::array<double, 3>;  // a direction, without pulling GLM into this header

inline constexpr double kReferenceAgreement = 1e-12;

struct CubatureBenchOptions {
  int cases_per_family = 200;
  std::vector<double> tolerances{1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
  double ratio_tolerance = 1e-10;   ///< the requested tolerance at which ratios are reported
  long long competitor_cap = 2'000'000;  ///< evaluations per competitor run
  unsigned seed = 20190117;
};
CubatureBenchOptions quick_options();

struct Run {  // one competitor at one requested tolerance on one case
  std::string competitor;
  double tolerance = 0.0, achieved_error = 0.0, estimate = 0.0, seconds = 0.0;
  long long evaluations = 0;
  bool capped = false;
};

/// One of our runs that missed its requested tolerance or whose estimate fell below the actual
/// error: the case, so that it can be reproduced with `ganzfeld eval`.
struct Miss {
  std::string model;
  Vec3Triple i{}, j{};
  double tolerance = 0.0, achieved_error = 0.0, estimate = 0.0;
  long long evaluations = 0;
};

struct FamilyResult {
  std::string name;
  int cases = 0, skipped = 0;
  double missed_rate = 0.0;      ///< fraction of our runs (all tolerances) missing the tolerance
  double dishonest_rate = 0.0;   ///< fraction of our runs whose estimate < actual error
  std::map<std::string, double> evals_ratio;  ///< geometric mean over cases, at ratio_tolerance
  std::map<std::string, int> capped;          ///< cases where the competitor hit the cap (ratio is a lower bound)
  double mc_error_ratio_equal_time = 0.0;     ///< geometric mean of MC error / our error
  std::vector<Run> runs;                      ///< every run, for the work–precision plot
  std::vector<Miss> misses;                   ///< our missed or dishonest runs
};

std::vector<FamilyResult> run_cubature_benchmark(const CubatureBenchOptions& options);

/// docs/performance.md: the ratio table per family, the targets of issue 8 as measured, and
/// the plot, stamped with `command`.
std::string performance_markdown(const std::vector<FamilyResult>& families, const CubatureBenchOptions& options,
                                 const std::string& command, const std::string& plot_file);

/// Work–precision plot: per competitor and requested tolerance, the geometric means over all
/// cases of evaluations (x) and achieved error (y), joined across tolerances.
void write_work_precision_plot(const std::vector<FamilyResult>& families, const std::string& path);

}  // namespace ganzfeld::bench
