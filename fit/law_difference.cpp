#include "fit/law_difference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

namespace ganzfeld::fit {

namespace {

Estimate law_at(const Model& model, const LawPoint& p, double tolerance) {
  const double rad = std::numbers::pi / 180.0;
  const Vec3 i = direction(p.theta_i_deg * rad, 0.0), j = direction(p.theta_j_deg * rad, p.phi_deg * rad);
  CubatureOptions options;
  options.abs_tol = tolerance;
  return evaluate_law(model, p.law, i, j, options);
}

}  // namespace

std::vector<LawPoint> law_geometries() {
  std::vector<LawPoint> points;
  for (double t : {0.0, 30.0, 60.0, 80.0}) points.push_back({Law::h, 0.0, t, 0.0, {}, {}});
  for (double t : {0.0, 30.0, 60.0, 80.0}) points.push_back({Law::a, t, 0.0, 0.0, {}, {}});
  for (const auto& [ti, tj, phi] : {std::array{30.0, 0.0, 0.0}, std::array{60.0, 45.0, 0.0},
                                    std::array{60.0, 45.0, 180.0}, std::array{120.0, 30.0, 0.0}})
    points.push_back({Law::g, ti, tj, phi, {}, {}});
  return points;
}

std::vector<LawPoint> data_laws(const Model& data, double tolerance) {
  std::vector<LawPoint> points = law_geometries();
  tbb::parallel_for(std::size_t{0}, points.size(),
                    [&](std::size_t k) { points[k].data = law_at(data, points[k], tolerance); });
  return points;
}

LawDifference law_difference(const std::vector<LawPoint>& data_points, const Model& fit, double tolerance) {
  LawDifference d;
  d.points = data_points;
  tbb::parallel_for(std::size_t{0}, d.points.size(),
                    [&](std::size_t k) { d.points[k].fit = law_at(fit, d.points[k], tolerance); });
  for (const LawPoint& p : d.points) {
    const double diff = std::abs(p.fit.value - p.data.value);
    double& max = p.law == Law::g ? d.max_g : p.law == Law::h ? d.max_h : d.max_a;
    max = std::max(max, diff);
    d.converged = d.converged && p.fit.converged && p.data.converged;
  }
  return d;
}

LawDifference law_difference(const Model& data, const Model& fit, double tolerance) {
  return law_difference(data_laws(data, tolerance), fit, tolerance);
}

}  // namespace ganzfeld::fit
