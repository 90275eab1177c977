// The machinery shared by the checks of `ganzfeld verify` (reports/verify.cpp for
// Koenderink & Pont, reports/verify_hvd.cpp for Edwards et al., reports/verify_ggx.cpp for GGX).
#pragma once

#include <functional>
#include <limits>
#include <vector>

#include "integrate/cubature.h"
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

/// Runs the jobs in parallel (results are reduced in order: deterministic) and fills the
/// check's errors, status and reference statistics.
CheckResult run_check(CheckResult check, const std::vector<Job>& jobs);

}  // namespace ganzfeld::verify_support
