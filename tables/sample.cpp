#include "tables/sample.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tables/frame.h"

namespace ganzfeld::tables {

bool is_even_axis(const Axis& axis) noexcept { return axis.name == kAxisPhi || axis.name == kAxisBeta; }

double filter_weight(double t, WeightRounding rounding) noexcept {
  switch (rounding) {
    case WeightRounding::nearest: return std::round(t * kFilterWeightSteps) / kFilterWeightSteps;
    case WeightRounding::truncate: return std::floor(t * kFilterWeightSteps) / kFilterWeightSteps;
    case WeightRounding::exact: break;
  }
  return t;
}

AxisTaps axis_taps(const Axis& axis, double u, Interpolation interpolation, WeightRounding rounding) noexcept {
  AxisTaps out;
  const int n = axis.count;
  const double s = std::clamp(u, 0.0, 1.0) * (n - 1);  // in [0, count - 1]
  const int k = static_cast<int>(std::min(std::floor(s), static_cast<double>(n - 2)));
  const double t = s - k;
  if (interpolation == Interpolation::linear || n < 4) {
    const double tq = filter_weight(t, rounding);
    out.taps = 2;
    out.node = {k, k + 1, k + 1, k + 1};
    out.weight = {1.0 - tq, tq, 0.0, 0.0};
    return out;
  }
  // Catmull–Rom on nodes k-1, k, k+1, k+2 (tangents (p[k+1] - p[k-1])/2).
  const double t2 = t * t, t3 = t2 * t;
  double w[4] = {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
                 0.5 * (t3 - t2)};
  const bool even = is_even_axis(axis);
  if (k == 0) {  // node -1 is missing: p[1] (even) or 3 p[0] - 3 p[1] + p[2]
    if (even) {
      w[2] += w[0];
    } else {
      w[1] += 3.0 * w[0];
      w[2] -= 3.0 * w[0];
      w[3] += w[0];
    }
    w[0] = 0.0;
  }
  if (k == n - 2) {  // node n is missing: p[n-2] (even) or 3 p[n-1] - 3 p[n-2] + p[n-3]
    if (even) {
      w[1] += w[3];
    } else {
      w[2] += 3.0 * w[3];
      w[1] -= 3.0 * w[3];
      w[0] += w[3];
    }
    w[3] = 0.0;
  }
  if (rounding != WeightRounding::exact) {  // nodes k, k+1: one linear fetch at fraction w2/(w1 + w2)
    const double middle = w[1] + w[2];
    const double f = filter_weight(w[2] / middle, rounding);
    w[1] = middle * (1.0 - f);
    w[2] = middle * f;
  }
  out.taps = 4;
  for (int d = 0; d < 4; ++d) {
    out.node[d] = std::clamp(k - 1 + d, 0, n - 1);
    out.weight[d] = w[d];
  }
  return out;
}

Sample sample_axes(const Table& table, std::span<const double> y, WeightRounding rounding) noexcept {
  const std::size_t dims = table.axes.size();
  if (dims == 0 || dims > 3 || y.size() != dims || table.value.size() != table.entries()) return {};
  AxisTaps taps[3];
  for (std::size_t d = 0; d < dims; ++d)
    taps[d] = axis_taps(table.axes[d], table.axes[d].index_coordinate(y[d]), table.interpolation, rounding);
  Sample out;
  const int c0 = taps[0].taps, c1 = dims > 1 ? taps[1].taps : 1, c2 = dims > 2 ? taps[2].taps : 1;
  const std::size_t n1 = dims > 1 ? table.axes[1].count : 1, n2 = dims > 2 ? table.axes[2].count : 1;
  for (int a = 0; a < c0; ++a)
    for (int b = 0; b < c1; ++b)
      for (int c = 0; c < c2; ++c) {
        const double w = taps[0].weight[a] * (dims > 1 ? taps[1].weight[b] : 1.0) * (dims > 2 ? taps[2].weight[c] : 1.0);
        if (w == 0.0) continue;
        const std::size_t m = (static_cast<std::size_t>(taps[0].node[a]) * n1 + (dims > 1 ? taps[1].node[b] : 0)) * n2 +
                              (dims > 2 ? taps[2].node[c] : 0);
        out.value += w * table.value[m];
        out.error += std::abs(w) * table.error[m];
      }
  if (table.frame == Frame::warped) {
    const double envelope = warp_envelope(table.warp, y[0]);
    out.value *= envelope;
    out.error *= envelope;
  }
  return out;
}

std::vector<double> axis_coordinates(const Table& table, std::span<const double> x) noexcept {
  if (table.frame == Frame::lobe && table.law == Law::g && x.size() == 3) {
    const std::array<double, 3> y = lobe_coordinates(table.peak, x[0], x[1], x[2]);
    return {y.begin(), y.end()};
  }
  if (table.frame == Frame::warped && table.law == Law::g && x.size() == 3) {
    const std::array<double, 3> y = warped_coordinates(table.peak, table.warp, table.axes[0], x[0], x[1], x[2]);
    return {y.begin(), y.end()};
  }
  return {x.begin(), x.end()};
}

Sample sample(const Table& table, std::span<const double> x, WeightRounding rounding) noexcept {
  const std::vector<double> y = axis_coordinates(table, x);
  return sample_axes(table, y, rounding);
}

WeightRounding own_rounding(const Table& table) noexcept {
  return table.filter == Filter::hardware ? WeightRounding::nearest : WeightRounding::exact;
}

std::vector<double> coordinates(Law law, const Vec3& i, const Vec3& j) noexcept {
  auto cos_theta = [](const Vec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? std::clamp(v.z / len, -1.0, 1.0) : 1.0;
  };
  switch (law) {
    case Law::h: return {cos_theta(j)};
    case Law::a: return {cos_theta(i)};
    default: break;
  }
  double phi = 0.0;
  const double ri = std::hypot(i.x, i.y), rj = std::hypot(j.x, j.y);
  if (ri > 0.0 && rj > 0.0) {
    // Angle between the horizontal projections, in [0, pi]: the laws of isotropic models are
    // even in the relative azimuth.
    const double c = (i.x * j.x + i.y * j.y) / (ri * rj);
    const double s = (i.x * j.y - i.y * j.x) / (ri * rj);
    phi = std::abs(std::atan2(s, c));
  }
  return {cos_theta(i), cos_theta(j), phi};
}

Sample sample(const Table& table, const Vec3& i, const Vec3& j, WeightRounding rounding) noexcept {
  const std::vector<double> x = coordinates(table.law, i, j);
  return sample(table, x, rounding);
}

}  // namespace ganzfeld::tables
