// The machinery shared by the checks of `ganzfeld verify` (reports/verify.cpp for Koenderink &
// Pont, reports/verify_hvd.cpp for Edwards et al., reports/verify_ggx.cpp for the microfacet
// models, reports/verify_catalogue.cpp for the catalogue's other printed forms).
#pragma once

#include <functional>
#include <limits>
#include <vector>

#include "integrate/cubature.h"
#include "integrate/laws.h"
#include "reports/verify.h"

namespace ganzfeld::verify_support {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// One comparison: the printed value, our corrected value (NaN if none), the cubature reference.
struct Sample {
  double printed = 0.0, corrected = kNaN, reference = 0.0, reference_error = 0.0;
  bool converged = true;
  long points = 1;
};
using Job = std::function<Sample()>;

/// Cubature options of every reference (kReferenceTolerance).
CubatureOptions reference_options();

/// Appends `spec` to the list of models a check ran on ("; "-separated).
void append_model(std::string& models, const std::string& spec);

/// A check's identity: id, source (paper and equation), the models it ran on, the claim as printed,
/// and for an erratum our corrected form and how it was derived.
CheckResult check_meta(std::string id, std::string source, std::string models, std::string printed,
                       std::string corrected = "", std::string explanation = "");

/// ∫ F(m) dm over the lune {m·n > 0, m·pole > 0}, with cut lines at angular distances `scales`
/// (and their multiples 4^k up to 1) from the normal n, and from the horizon when `at_horizon`.
Estimate integrate_over_lune(const Vec3& pole, const std::function<double(const Vec3&)>& F,
                             const std::vector<double>& scales, bool at_horizon = false,
                             CubatureOptions options = reference_options());

/// A job comparing `printed` (and `corrected`) with ∫ F(m) dm over the hemisphere m·n > 0 (the lune
/// with pole n, cut as integrate_over_lune): the normalization of a distribution or a density.
Job hemisphere_job(std::function<double(const Vec3&)> F, std::vector<double> scales, double printed,
                   double corrected = kNaN, bool at_horizon = false);

/// Runs the jobs in parallel (results are reduced in order: deterministic) and fills the
/// check's errors, status and reference statistics.
CheckResult run_check(CheckResult check, const std::vector<Job>& jobs);

}  // namespace ganzfeld::verify_support
