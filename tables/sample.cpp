#include "tables/sample.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tables/frame.h"
#include "util/angles.h"

namespace ganzfeld::tables {

bool is_even_axis(const Axis& axis) noexcept { return axis.name == kAxisPhi || axis.name == kAxisBeta; }

namespace {
/// The value and the per-node error bound a lookup blends at `site`.
Sample blend(const Lookup& lookup, const Lookup::Site& site, WeightRounding rounding) noexcept {
  const Table& table = lookup.table();
  Sample out;
  lookup.visit(
      site,
      [&](std::size_t entry, double w) {
        out.value += w * table.value[entry];
        out.error += std::abs(w) * table.error[entry];
      },
      rounding);
  return out;
}

/// Moves the weight of Catmull–Rom's tap `missing` (0 or 3), a node beyond the axis' end, onto
/// the taps that stand in for it, counted inwards from it: on an even axis its mirror image about
/// the first (the second), else the quadratic extrapolation 3 p[first] - 3 p[second] + p[third].
void fold_missing_tap(double (&w)[4], int missing, bool even) noexcept {
  const int inward = missing == 0 ? 1 : -1;
  const int first = missing + inward, second = first + inward, third = second + inward;
  if (even) {
    w[second] += w[missing];
  } else {
    w[first] += 3.0 * w[missing];
    w[second] -= 3.0 * w[missing];
    w[third] += w[missing];
  }
  w[missing] = 0.0;
}
}  // namespace

AxisTaps catmull_rom_taps(const Axis& axis, int k, double t, WeightRounding rounding) noexcept {
  return catmull_rom_taps(axis.count, is_even_axis(axis), k, t, rounding);
}

AxisTaps catmull_rom_taps(int count, bool even, int k, double t, WeightRounding rounding) noexcept {
  // Catmull–Rom on nodes k-1, k, k+1, k+2 (tangents (p[k+1] - p[k-1])/2).
  const int n = count;
  const double t2 = t * t, t3 = t2 * t;
  double w[4] = {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
                 0.5 * (t3 - t2)};
  if (k == 0) fold_missing_tap(w, 0, even);      // node -1: p[1] (even) or 3 p[0] - 3 p[1] + p[2]
  if (k == n - 2) fold_missing_tap(w, 3, even);  // node n: p[n-2] (even) or 3 p[n-1] - 3 p[n-2] + p[n-3]
  if (rounding != WeightRounding::exact) {       // nodes k, k+1: one linear fetch at fraction w2/(w1 + w2)
    const double middle = w[1] + w[2];
    const double f = filter_weight(w[2] / middle, rounding);
    w[1] = middle * (1.0 - f);
    w[2] = middle * f;
  }
  AxisTaps out;
  out.taps = 4;
  for (int d = 0; d < 4; ++d) {
    out.node[d] = std::clamp(k - 1 + d, 0, n - 1);
    out.weight[d] = w[d];
  }
  return out;
}

AxisTaps bspline_taps(int count, double u, WeightRounding rounding) noexcept {
  const double s = 1.0 + std::clamp(u, 0.0, 1.0) * (count - 3);  // in [1, count - 2]
  const int k = std::min(static_cast<int>(s), count - 3);
  const double t = s - k, r = 1.0 - t, t2 = t * t, t3 = t2 * t;
  // The uniform cubic B-spline's weights of coefficients k-1 .. k+2 (each >= 0, sum 1), read as two
  // linear fetches: (k-1, k) with weight b0 + b1 >= 1/6, (k+1, k+2) with b2 + b3 >= 1/6.
  const double b[4] = {r * r * r / 6.0, (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0, (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
                       t3 / 6.0};
  AxisTaps out;
  out.taps = 4;
  for (int p = 0; p < 2; ++p) {
    const double g = b[2 * p] + b[2 * p + 1];
    const double f = filter_weight(b[2 * p + 1] / g, rounding);
    out.node[2 * p] = k - 1 + 2 * p;
    out.node[2 * p + 1] = k + 2 * p;
    out.weight[2 * p] = g * (1.0 - f);
    out.weight[2 * p + 1] = g * f;
  }
  return out;
}

bool same_lookup(const Table& a, const Table& b) noexcept {
  if (a.law != b.law || a.frame != b.frame || a.interpolation != b.interpolation || a.axes != b.axes) return false;
  if (a.frame != Frame::cosines && a.peak != b.peak) return false;
  if (a.frame == Frame::warped) {  // the offset axis and the envelope follow each table's own warp
    const Warp &p = a.warp, &q = b.warp;
    if (p.mix != q.mix || p.envelope != q.envelope || p.beta_whitening != q.beta_whitening || p.samples != q.samples)
      return false;
  }
  return true;
}

Lookup::Lookup(const Table& table) noexcept : table_(&table), dims_(table.axes.size()) {
  if (dims_ == 0 || dims_ > 3) return;
  std::size_t entries = 1;
  for (std::size_t d = dims_; d-- > 0;) {
    const Axis& axis = table.axes[d];
    stride_[d] = entries;
    entries *= static_cast<std::size_t>(axis.count);
    index_[d] = AxisIndex(axis);
    count_[d] = axis.count;
    even_[d] = is_even_axis(axis);
  }
  fits_ = table.value.size() == entries;
}

Lookup::Site Lookup::at_axes(std::span<const double> y) const noexcept {
  Site site;
  if (!fits_ || y.size() != dims_) return site;
  for (std::size_t d = 0; d < dims_; ++d) site.u[d] = index_[d](y[d]);
  site.scale = table_->frame == Frame::warped ? warp_envelope(table_->warp, y[0]) : 1.0;
  site.valid = true;
  return site;
}

Lookup::Site Lookup::at_law(const Point& x) const noexcept {
  const Table& t = *table_;
  if (!(t.law == Law::g && t.frame != Frame::cosines && x.size == 3 && fits_ && dims_ == 3))
    return at_axes(axis_point(t, x.span()).span());
  const LobeComponents c = x.has_azimuth_trig
                               ? lobe_components(t.peak, x.x[0], x.x[1], x.cos_phi, x.sin_phi)
                               : lobe_components(t.peak, x.x[0], x.x[1], std::cos(x.x[2]), std::sin(x.x[2]));
  Site site;
  site.u[0] = index_[0](c.theta_j);
  if (t.frame == Frame::warped) {
    const WarpSample at = warp_at_index(t.warp, site.u[0]);
    site.u[1] = index_[1](warped_offset(at, t.warp.mix, c.ip, c.ie1, c.ie2, c.psi));
    site.u[2] = index_[2](warped_beta(at, t.warp.beta_whitening, c.ie1, c.ie2, c.beta));
    site.scale = warp_envelope(t.warp, c.cos_theta_j, c.sin_theta_j);
  } else {
    site.u[1] = index_[1](c.psi);
    site.u[2] = index_[2](c.beta);
  }
  site.valid = true;
  return site;
}

Sample sample_axes(const Table& table, std::span<const double> y, WeightRounding rounding) noexcept {
  const Lookup lookup(table);
  return blend(lookup, lookup.at_axes(y), rounding);
}

Point axis_point(const Table& table, std::span<const double> x) noexcept {
  Point out;
  if (table.frame == Frame::lobe && table.law == Law::g && x.size() == 3) {
    out.x = lobe_coordinates(table.peak, x[0], x[1], x[2]);
    out.size = 3;
    return out;
  }
  if (table.frame == Frame::warped && table.law == Law::g && x.size() == 3) {
    out.x = warped_coordinates(table.peak, table.warp, table.axes[0], x[0], x[1], x[2]);
    out.size = 3;
    return out;
  }
  out.size = std::min(x.size(), out.x.size());
  std::copy_n(x.begin(), out.size, out.x.begin());
  return out;
}

std::vector<double> axis_coordinates(const Table& table, std::span<const double> x) noexcept {
  const Point y = axis_point(table, x);
  return {y.x.begin(), y.x.begin() + static_cast<std::ptrdiff_t>(y.size)};
}

Sample sample(const Table& table, std::span<const double> x, WeightRounding rounding) noexcept {
  Point p;
  if (x.size() <= p.x.size()) p.size = x.size(), std::copy(x.begin(), x.end(), p.x.begin());  // else fits no table
  const Lookup lookup(table);
  return blend(lookup, lookup.at_law(p), rounding);
}

WeightRounding own_rounding(const Table& table) noexcept {
  return table.filter == Filter::hardware ? WeightRounding::nearest : WeightRounding::exact;
}

Point law_point(Law law, const Vec3& i, const Vec3& j) noexcept {
  auto cos_theta = [](const Vec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? std::clamp(v.z / len, -1.0, 1.0) : 1.0;
  };
  Point out;
  switch (law) {
    case Law::h: out.x[0] = cos_theta(j), out.size = 1; return out;
    case Law::a: out.x[0] = cos_theta(i), out.size = 1; return out;
    default: break;
  }
  // Angle between the horizontal projections, in [0, pi]: the laws of isotropic models are even
  // in the relative azimuth.
  const bool along_n = (i.x == 0.0 && i.y == 0.0) || (j.x == 0.0 && j.y == 0.0);
  const double cross = i.x * j.y - i.y * j.x, dot = i.x * j.x + i.y * j.y;
  const double phi = along_n ? 0.0 : std::abs(util::atan2_fast(cross, dot));
  out.x = {cos_theta(i), cos_theta(j), phi};
  out.size = 3;
  // |cross|^2 + dot^2 = |i_t|^2 |j_t|^2 > 0 off the normal (Lagrange's identity).
  const double r = along_n ? 0.0 : std::sqrt(cross * cross + dot * dot);
  if (r > 0.0) out.has_azimuth_trig = true, out.cos_phi = dot / r, out.sin_phi = std::abs(cross) / r;
  return out;
}

std::vector<double> coordinates(Law law, const Vec3& i, const Vec3& j) noexcept {
  const Point x = law_point(law, i, j);
  return {x.x.begin(), x.x.begin() + static_cast<std::ptrdiff_t>(x.size)};
}

Sample sample(const Table& table, const Vec3& i, const Vec3& j, WeightRounding rounding) noexcept {
  const Lookup lookup(table);
  return blend(lookup, lookup.at_law(law_point(table.law, i, j)), rounding);
}

}  // namespace ganzfeld::tables
