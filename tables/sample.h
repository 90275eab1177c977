// Table lookup (docs/lut-format.md, "Sampling"): the law's coordinates are turned into the
// table's axis coordinates (its frame), each axis coordinate into an index coordinate u (the
// mapping inverted), and the nodes around u (count - 1) are blended: multilinearly (2 per axis,
// what a GPU's linear filter does with texel coordinate u (count - 1) + 0.5) or by Catmull–Rom
// (4 per axis). Coordinates outside an axis are clamped to its ends. The returned error is the
// same blend of the stored per-node errors with |weights|: how far the lookup is from blending
// the exact node values. It does NOT include the interpolation error between nodes, which
// Table::lookup_error (validated at bake time) does.
#pragma once

#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include "models/model.h"
#include "tables/table.h"

namespace ganzfeld::tables {

struct Sample {
  double value = 0.0;
  double error = 0.0;
};

/// Lookup at the law's coordinates x (g: i·n, j·n, relative azimuth in [0, pi]; h: j·n; a: i·n),
/// whatever the table's frame. `rounding` emulates a hardware filter's 8-bit weights
/// (WeightRounding::nearest or truncate: every weight a texture() call of export/glsl.cpp's
/// hardware path computes is rounded to a multiple of 1/256); exact: full precision.
Sample sample(const Table& table, std::span<const double> x, WeightRounding rounding = WeightRounding::exact) noexcept;

/// Lookup at the table's own axis coordinates y (one per axis, in the axes' units); a warped
/// table's blend is multiplied by its envelope A(theta_j) (tables/frame.h).
Sample sample_axes(const Table& table, std::span<const double> y,
                   WeightRounding rounding = WeightRounding::exact) noexcept;

/// Whether lookups in a and b blend the same entries with the same weights at every point: the
/// same law, frame, peak, interpolation and axes. Tables of several lobes that share a lookup can
/// be summed entry by entry and looked up once (the laws are linear in f: rasterizer/shading.cpp).
bool same_lookup(const Table& a, const Table& b) noexcept;

/// Up to three coordinates without allocating (the per-pixel form of coordinates and
/// axis_coordinates).
struct Point {
  std::array<double, 3> x{};
  std::size_t size = 0;
  /// g's cos phi and |sin phi| when law_point found them from the directions (no trigonometry);
  /// otherwise they are taken from phi = x[2].
  bool has_azimuth_trig = false;
  double cos_phi = 1.0, sin_phi = 0.0;
  std::span<const double> span() const noexcept { return {x.data(), size}; }
};
/// coordinates(law, i, j) as a Point.
Point law_point(Law law, const Vec3& i, const Vec3& j) noexcept;
/// axis_coordinates(table, x) as a Point.
Point axis_point(const Table& table, std::span<const double> x) noexcept;

/// The table's axis coordinates of the law's coordinates x (identity for the cosines frame;
/// (theta_j, psi, beta) or (theta_j, offset, beta) of tables/frame.h for the lobe and warped frames).
std::vector<double> axis_coordinates(const Table& table, std::span<const double> x) noexcept;

/// Nodes and weights of one axis of a lookup at index coordinate u: `taps` nodes (2 linear, 4
/// Catmull–Rom and b-spline) at node[k] with weight[k]; the weights sum to 1. Catmull–Rom's missing node
/// beyond an axis end is the even reflection for azimuths (phi, beta: the laws are even there)
/// and the quadratic extrapolation 3 p0 - 3 p1 + p2 otherwise, folded into the real nodes.
struct AxisTaps {
  int taps = 2;
  std::array<int, 4> node{};
  std::array<double, 4> weight{};
};
/// t rounded to a multiple of 1/kFilterWeightSteps as `rounding` says (exact: t itself).
inline double filter_weight(double t, WeightRounding rounding) noexcept {
  switch (rounding) {
    case WeightRounding::nearest: return std::round(t * kFilterWeightSteps) / kFilterWeightSteps;
    case WeightRounding::truncate: return std::floor(t * kFilterWeightSteps) / kFilterWeightSteps;
    case WeightRounding::exact: break;
  }
  return t;
}
/// The Catmull–Rom taps of cell k (nodes k-1 .. k+2) at fraction t of an axis of >= 4 nodes; with
/// `rounding`, the fraction w2 / (w1 + w2) of its middle linear fetch is rounded as a hardware
/// filter's 8-bit weights are.
AxisTaps catmull_rom_taps(const Axis& axis, int k, double t, WeightRounding rounding = WeightRounding::exact) noexcept;
/// The same on an axis of `count` nodes, even (is_even_axis) or not.
AxisTaps catmull_rom_taps(int count, bool even, int k, double t, WeightRounding rounding) noexcept;
/// The b-spline taps at index coordinate u of an axis of `count` >= kBSplineMinCount coefficients
/// (tables/bspline.h: s = 1 + u (count - 3), cell k = min(floor s, count - 3), coefficients k-1 ..
/// k+2, all stored, weights >= 0). A hardware filter reads them as two linear fetches of
/// neighbouring coefficients, (k-1, k) at fraction b1 / (b0 + b1) and (k+1, k+2) at b3 / (b2 + b3):
/// with `rounding`, each fraction is rounded as a hardware filter's 8-bit weights are.
AxisTaps bspline_taps(int count, double u, WeightRounding rounding) noexcept;
/// The cell of index coordinate u on an axis: s = u (count - 1), node k = min(floor s, count - 2),
/// fraction t = s - k.
struct Cell {
  int k = 0;
  double t = 0.0;
};
inline Cell cell(int count, double u) noexcept {
  const double s = std::clamp(u, 0.0, 1.0) * (count - 1);  // in [0, count - 1]
  const int k = std::min(static_cast<int>(s), count - 2);  // s >= 0: truncation is the floor
  return {k, s - k};
}
inline Cell cell(const Axis& axis, double u) noexcept { return cell(axis.count, u); }
/// With `rounding`, the weights are those of a hardware filter with 8-bit sub-texel precision:
/// linear's t, and Catmull–Rom's fraction w2 / (w1 + w2) of its middle linear fetch, rounded to
/// a multiple of 1/256 (to nearest or down). Inline: a lookup makes one per axis.
/// On an axis of `count` nodes, even (is_even_axis) or not.
inline AxisTaps axis_taps(int count, bool even, double u, Interpolation interpolation,
                          WeightRounding rounding = WeightRounding::exact) noexcept {
  if (interpolation == Interpolation::bspline && count >= min_count(Interpolation::bspline))
    return bspline_taps(count, u, rounding);
  const Cell c = cell(count, u);
  if (interpolation == Interpolation::catmull_rom && count >= min_count(Interpolation::catmull_rom))
    return catmull_rom_taps(count, even, c.k, c.t, rounding);
  const double t = filter_weight(c.t, rounding);
  return {2, {c.k, c.k + 1, c.k + 1, c.k + 1}, {1.0 - t, t, 0.0, 0.0}};
}
/// Whether an axis is an azimuth about which the law is even (Catmull–Rom reflects there).
bool is_even_axis(const Axis& axis) noexcept;
inline AxisTaps axis_taps(const Axis& axis, double u, Interpolation interpolation,
                          WeightRounding rounding = WeightRounding::exact) noexcept {
  return axis_taps(axis.count, is_even_axis(axis), u, interpolation, rounding);
}

/// A table's lookup with what does not depend on the point computed once (the axes' mappings,
/// strides, the even axes): the one definition of what a lookup blends. sample, sample_axes and
/// for_each_node make one per call; a renderer keeps one per table (rasterizer/shading.cpp).
/// The table must outlive it.
class Lookup {
 public:
  explicit Lookup(const Table& table) noexcept;
  const Table& table() const noexcept { return *table_; }

  /// Where a lookup lands: each axis' index coordinate u and what the blend is multiplied by (a
  /// warped table's envelope A(theta_j), tables/frame.h; 1 for other tables). valid is false
  /// when the point or the table's data do not fit its axes.
  struct Site {
    std::array<double, 3> u{};
    double scale = 1.0;
    bool valid = false;
  };
  /// At the table's axis coordinates y (one per axis, in the axes' units).
  Site at_axes(std::span<const double> y) const noexcept;
  /// At the law's coordinates x (law_point, or a Point of the g/h/a coordinates): the frame's
  /// coordinates found as axis_point finds them; a warped table's theta_j index serves both its
  /// axis and its warp, and its envelope takes cos and sin theta_j from x.
  Site at_law(const Point& x) const noexcept;

  /// Calls visit(entry, weight) for every entry the lookup at `site` blends (entry index =
  /// ((k0 n1) + k1) n2 + k2), each node's weight site.scale times the product w0 w1 w2 of its
  /// axes' tap weights (Catmull–Rom leaves entries of zero weight out; a linear blend may visit
  /// them); `rounding` as for axis_taps. Visits nothing and returns false for an invalid site.
  /// Inline, so that a caller summing several channels per entry pays no more than sample_axes.
  template <class Visit>
  bool visit(const Site& site, Visit&& visit, WeightRounding rounding = WeightRounding::exact) const noexcept {
    if (!site.valid) return false;
    const std::size_t* stride = stride_.data();
    if (table_->interpolation == Interpolation::linear) {  // 2 taps per axis: (1 - t, t) at nodes k, k + 1
      Cell c[3] = {{0, 0.0}, {0, 0.0}, {0, 0.0}};
      for (std::size_t d = 0; d < dims_; ++d) {
        c[d] = cell(count_[d], site.u[d]);
        c[d].t = filter_weight(c[d].t, rounding);
      }
      const std::size_t base = c[0].k * stride[0] + c[1].k * stride[1] + c[2].k * stride[2];
      const double w0[2] = {site.scale * (1.0 - c[0].t), site.scale * c[0].t}, w1[2] = {1.0 - c[1].t, c[1].t},
                   w2[2] = {1.0 - c[2].t, c[2].t};
      const int n1 = dims_ > 1 ? 2 : 1, n2 = dims_ > 2 ? 2 : 1;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < n1; ++b) {
          const double wab = dims_ > 1 ? w0[a] * w1[b] : w0[a];
          for (int e = 0; e < n2; ++e)
            visit(base + a * stride[0] + b * stride[1] + e * stride[2], dims_ > 2 ? wab * w2[e] : wab);
        }
      return true;
    }
    AxisTaps taps[3];
    for (std::size_t d = 0; d < 3; ++d)
      taps[d] = d < dims_ ? axis_taps(count_[d], even_[d], site.u[d], table_->interpolation, rounding)
                          : AxisTaps{1, {0, 0, 0, 0}, {1.0, 0.0, 0.0, 0.0}};  // a missing axis: one tap of weight 1
    for (int a = 0; a < taps[0].taps; ++a) {
      const double wa = site.scale * taps[0].weight[a];
      const std::size_t ea = static_cast<std::size_t>(taps[0].node[a]) * stride[0];
      for (int b = 0; b < taps[1].taps; ++b) {
        const double wab = wa * taps[1].weight[b];
        const std::size_t eab = ea + static_cast<std::size_t>(taps[1].node[b]) * stride[1];
        for (int c = 0; c < taps[2].taps; ++c) {
          const double w = wab * taps[2].weight[c];
          if (w != 0.0) visit(eab + static_cast<std::size_t>(taps[2].node[c]) * stride[2], w);
        }
      }
    }
    return true;
  }

 private:
  const Table* table_;
  std::size_t dims_ = 0;
  bool fits_ = false;  ///< 1 to 3 axes and one value per node
  std::array<AxisIndex, 3> index_{};
  std::array<int, 3> count_{};
  std::array<bool, 3> even_{};
  std::array<std::size_t, 3> stride_{};
};

/// What a lookup at axis coordinates y blends: Lookup(table).visit(at_axes(y), visit, rounding).
template <class Visit>
bool for_each_node(const Table& table, std::span<const double> y, Visit&& visit,
                   WeightRounding rounding = WeightRounding::exact) noexcept {
  const Lookup lookup(table);
  return lookup.visit(lookup.at_axes(y), visit, rounding);
}

/// The axis coordinates of directions i, j (local frame, n = +z; need not be unit) for the
/// table's law: g -> (i·n, j·n, relative azimuth in [0, pi]); h -> (j·n); a -> (i·n).
/// The relative azimuth of a direction along ±n is taken as 0 (the laws do not depend on it); it
/// is atan2 of the tangential parts' cross and dot products, unnormalized (atan2 needs no scale),
/// as the exported GLSL computes it (export/glsl.cpp, gz_relative_azimuth).
std::vector<double> coordinates(Law law, const Vec3& i, const Vec3& j) noexcept;

/// sample(table, coordinates(table.law, i, j)).
Sample sample(const Table& table, const Vec3& i, const Vec3& j,
              WeightRounding rounding = WeightRounding::exact) noexcept;

/// The lookup the table's bound is for: its filter's (hardware: 8-bit weights rounded to nearest,
/// as `ganzfeld sample --hardware-filter` does; texel_fetch: exact).
WeightRounding own_rounding(const Table& table) noexcept;

}  // namespace ganzfeld::tables
