// Small helpers shared by the model tests.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "integrate/cubature.h"
#include "util/error.h"
#include "models/spec.h"

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

/// f is finite, non-negative and reciprocal to the last bit (the formulas are symmetric
/// expressions) for every pair of `dirs`.
inline void expect_finite_non_negative_reciprocal(const Model& m, const std::vector<Vec3>& dirs,
                                                  const std::string& label) {
  for (const Vec3& i : dirs)
    for (const Vec3& j : dirs) {
      const double f = m.f(i, j);
      ASSERT_TRUE(std::isfinite(f)) << label;
      ASSERT_GE(f, 0.0) << label;
      ASSERT_EQ(f, m.f(j, i)) << label;
    }
}

/// Parsing `spec` must fail with a one-line InputError that contains every fragment (the model,
/// the key=value, the allowed range...).
inline void expect_input_error(const std::string& spec, const std::vector<std::string>& fragments) {
  try {
    parse_model(spec);
    ADD_FAILURE() << spec << " was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const auto& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << spec << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << spec << ": " << what;
  }
}

}  // namespace ganzfeld::testing_support
