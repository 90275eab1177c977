#include "tables/sample.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ganzfeld::tables {

Sample sample(const Table& table, std::span<const double> x) noexcept {
  const std::size_t dims = table.axes.size();
  if (dims == 0 || dims > 3 || x.size() != dims || table.value.size() != table.entries()) return {};
  std::size_t lo[3] = {0, 0, 0};
  double frac[3] = {0, 0, 0};
  for (std::size_t d = 0; d < dims; ++d) {
    const Axis& axis = table.axes[d];
    const double s = axis.index_coordinate(x[d]) * (axis.count - 1);  // in [0, count - 1]
    const auto k = static_cast<std::size_t>(std::min(std::floor(s), static_cast<double>(axis.count - 2)));
    lo[d] = k;
    frac[d] = s - static_cast<double>(k);
  }
  Sample out;
  for (unsigned corner = 0; corner < (1u << dims); ++corner) {
    double weight = 1.0;
    std::size_t m = 0;
    for (std::size_t d = 0; d < dims; ++d) {
      const bool up = (corner >> d) & 1u;
      weight *= up ? frac[d] : 1.0 - frac[d];
      m = m * static_cast<std::size_t>(table.axes[d].count) + lo[d] + (up ? 1 : 0);
    }
    if (weight == 0.0) continue;
    out.value += weight * table.value[m];
    out.error += weight * table.error[m];
  }
  return out;
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

Sample sample(const Table& table, const Vec3& i, const Vec3& j) noexcept {
  const std::vector<double> x = coordinates(table.law, i, j);
  return sample(table, x);
}

}  // namespace ganzfeld::tables
