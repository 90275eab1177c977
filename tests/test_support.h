// Small helpers shared by the model tests.
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "integrate/cubature.h"
#include "integrate/laws.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld::testing_support {

/// Cubature options with the given tolerance and evaluation budget.
inline CubatureOptions cubature_options(double abs_tol, long long max_evaluations = 5'000'000) {
  CubatureOptions o;
  o.abs_tol = abs_tol;
  o.max_evaluations = max_evaluations;
  return o;
}

/// f against values computed by hand (mpmath, 30 digits, from a paper's formulas written with
/// angles rather than our vector forms): a few ulps of each of ~30 double operations.
inline constexpr double kHandRelative = 1e-13;

/// The unit direction at polar angle theta and azimuth phi in degrees (direction, integrate/laws.h).
inline Vec3 direction_deg(double theta_deg, double phi_deg = 0.0) {
  return direction(theta_deg * std::numbers::pi / 180, phi_deg * std::numbers::pi / 180);
}

/// Incidence cosines from normal to 1e-3 from the horizon, where the energy claims are tested.
inline const std::vector<double> kIncidenceCosines{1.0, 0.9, 0.7, 0.5, 0.3, 0.1, 0.03, 0.01, 1e-3};

/// Absolute tolerance asked of the cubature for albedos; its estimate is the raw Kronrod–Gauss
/// difference (integrate/cubature.h), a pessimistic bound, so results are within it.
inline constexpr double kAlbedoCubatureTol = 1e-6;
/// Slack on albedo comparisons: ten times the requested cubature tolerance.
inline constexpr double kAlbedoTol = 10 * kAlbedoCubatureTol;

/// Albedo a(i) by the engine's cubature (kAlbedoCubatureTol) for i at the given cosine and
/// azimuth; must converge.
inline double albedo_at(const Model& m, double cos_i, double phi = 0.3) {
  const Estimate e = albedo(m, direction_from_cos(cos_i, phi), cubature_options(kAlbedoCubatureTol));
  EXPECT_TRUE(e.converged) << m.spec() << " cos_i=" << cos_i;
  return e.value;
}

/// f is finite and non-negative for every pair of `dirs`, and 0 where either direction lies below
/// the horizon (models/model.h).
inline void expect_finite_non_negative(const Model& m, const std::vector<Vec3>& dirs, const std::string& label) {
  for (const Vec3& i : dirs)
    for (const Vec3& j : dirs) {
      const double f = m.f(i, j);
      ASSERT_TRUE(std::isfinite(f)) << label << " i.z=" << i.z << " j.z=" << j.z;
      ASSERT_GE(f, 0.0) << label << " i.z=" << i.z << " j.z=" << j.z;
    }
  const Vec3 below{0.6, 0.0, -0.8}, up{0.0, 0.0, 1.0};
  EXPECT_EQ(m.f(below, up), 0.0) << label << ": i below the horizon";
  EXPECT_EQ(m.f(up, below), 0.0) << label << ": j below the horizon";
}

/// expect_finite_non_negative, and reciprocal to the last bit (the formulas are symmetric
/// expressions) for every pair of `dirs`.
inline void expect_finite_non_negative_reciprocal(const Model& m, const std::vector<Vec3>& dirs,
                                                  const std::string& label) {
  expect_finite_non_negative(m, dirs, label);
  for (const Vec3& i : dirs)
    for (const Vec3& j : dirs) ASSERT_EQ(m.f(i, j), m.f(j, i)) << label << " i.z=" << i.z << " j.z=" << j.z;
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
