// `ganzfeld bench genz`: the cubature's error estimate judged on the standard test suite for
// adaptive cubature, Genz's six families (A. Genz, "A package for testing multiple integration
// subroutines", in Numerical Integration, Reidel 1987, pp. 337–340; his TESTPACK's difficulty
// levels), in 1-D and 2-D on the unit box, with their closed-form integrals:
//   oscillatory    cos(2π u₁ + Σ aᵢ xᵢ)            difficulty Σ aᵢ = 110 / n^1.5
//   product peak   Π (aᵢ⁻² + (xᵢ − uᵢ)²)⁻¹          600 / n²
//   corner peak    (1 + Σ aᵢ xᵢ)^−(n+1)             600 / n²
//   Gaussian       exp(−Σ aᵢ² (xᵢ − uᵢ)²)           100 / n
//   C0             exp(−Σ aᵢ |xᵢ − uᵢ|)             150 / n²
//   discontinuous  0 where some xᵢ > uᵢ, else exp(Σ aᵢ xᵢ)   100 / n²
// with aᵢ, uᵢ uniform in [0, 1] (seeded), the aᵢ scaled to the difficulty. Every competitor
// integrates the same integrand, counted by one wrapper with one evaluation cap, to the same
// absolute target (relative tolerance × |exact|): ours with no hints (the box's ends as its only
// cuts, as a user's own integrand), S. G. Johnson's hcubature and pcubature, Boost.Math's
// adaptive gauss_kronrod<15> and tanh_sinh (nested in 2-D). A run is *dishonest* when it claims
// the target (converged, or its estimate within it) and |value − exact| exceeds its estimate by
// more than the rounding of doubles (kRoundingUlps of the integrand's L1 norm).
// C0's kinks and the discontinuous family's jumps lie on lines; a run where some such line had
// no evaluated point on one of its sides (it lies between the box's end and the nodes nearest to
// it) is *unseen*: no rule can tell the integrand there from its smooth continuation, and such a
// run is counted apart. The corner peak has its corner at the origin.
#pragma once

#include <array>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace ganzfeld::bench {

enum class GenzFamily { oscillatory, product_peak, corner_peak, gaussian, c0, discontinuous };
inline constexpr std::array<GenzFamily, 6> kGenzFamilies{GenzFamily::oscillatory, GenzFamily::product_peak,
                                                         GenzFamily::corner_peak, GenzFamily::gaussian,
                                                         GenzFamily::c0,          GenzFamily::discontinuous};
const char* to_string(GenzFamily family);

/// One integrand of a family: its parameters and its exact integral over [0, 1]^dimension.
struct GenzInstance {
  GenzFamily family = GenzFamily::oscillatory;
  int dimension = 1;
  std::array<double, 2> a{}, u{};
  long double exact = 0.0L;
  double operator()(const double* x) const;
  /// ∫|f| over the box (|exact| but for the oscillatory family, bounded there by the box's volume).
  double l1_norm() const;
};
/// Genz's random instance at his difficulty level; the exact integral in long double.
GenzInstance make_genz_instance(GenzFamily family, int dimension, std::mt19937_64& rng);
long double genz_exact(const GenzInstance& instance);

/// The lines where C0 bends and the discontinuous family jumps, for the "unseen" verdict: along
/// axis `axis` at x = `at`, over the other coordinate below `extent` (2-D; 1 for C0's full lines).
struct SingularLine {
  int axis = 0;
  double at = 0.0, extent = 1.0;
};
std::vector<SingularLine> singular_lines(const GenzInstance& instance);

/// Relative tolerances below this are refused: 50 ulps, the rounding every panel carries.
double min_relative_tolerance();

/// The sample the suite is judged on: at least this many seeded instances per family and dimension,
/// each at every relative tolerance from 1e-3 to 1e-12 (the defaults below). A smaller run (hours
/// on 2 cores otherwise) says in its report that it missed this.
inline constexpr int kGenzInstancesTarget = 500;

struct GenzOptions {
  int instances = kGenzInstancesTarget;  ///< per family and dimension; every instance runs at every tolerance
  std::vector<double> tolerances{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  long long budget = 1'000'000;  ///< evaluations per competitor run
  std::vector<int> dimensions{1, 2};
  unsigned seed = 19870101;
};
GenzOptions quick_genz_options();
/// Throws InputError for no instances, a tolerance outside [min_relative_tolerance(), 1), a
/// budget below one panel of ours (15^dimension) or a dimension other than 1 or 2.
void check_genz_options(const GenzOptions& options);

struct GenzRun {
  std::string competitor;
  double tolerance = 0.0;  ///< relative
  double error = 0.0, estimate = 0.0, resolution = 0.0;
  long long evaluations = 0;
  bool claimed = false, capped = false, seen = true;
  bool dishonest() const { return claimed && error > estimate + resolution; }
};

/// One competitor on one family in one dimension, over every instance and tolerance.
struct GenzCell {
  GenzFamily family = GenzFamily::oscillatory;
  int dimension = 1;
  std::string competitor;
  int runs = 0, dishonest = 0, dishonest_unseen = 0, not_converged = 0, capped = 0;
  double worst_ratio = 0.0;         ///< largest error / (estimate + resolution) of a dishonest seen run
  double worst_unseen_ratio = 0.0;  ///< the same over the unseen ones
  double log_evaluations = 0.0;     ///< summed log, for the geometric mean
  long long evaluations = 0;
  double geometric_mean_evaluations() const;
};

/// The competitors, in table order.
const std::vector<std::string>& genz_competitors();

/// Runs the whole suite (instances in parallel, results in a fixed order).
std::vector<GenzCell> run_genz_benchmark(const GenzOptions& options);

/// docs/reliability-genz.md: the method, the tables, the targets met or missed.
std::string genz_markdown(const std::vector<GenzCell>& cells, const GenzOptions& options, const std::string& command,
                          double seconds);

}  // namespace ganzfeld::bench
