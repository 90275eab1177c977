// Small helpers shared by the model tests.
#pragma once

#include <vector>

#include "integrate/cubature.h"

namespace ganzfeld::testing_support {

/// Cubature options with the given tolerance and evaluation budget.
inline CubatureOptions cubature_options(double abs_tol, long long max_evaluations = 5'000'000) {
  CubatureOptions o;
  o.abs_tol = abs_tol;
  o.max_evaluations = max_evaluations;
  return o;
}

/// Incidence cosines from normal to 1e-3 from the horizon, where the energy claims are tested.
inline const std::vector<double> kIncidenceCosines{1.0, 0.9, 0.7, 0.5, 0.3, 0.1, 0.03, 0.01, 1e-3};

}  // namespace ganzfeld::testing_support
