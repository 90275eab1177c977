// Table lookup (docs/lut-format.md, "Sampling"): the law's coordinates are turned into the
// table's axis coordinates (its frame), each axis coordinate into an index coordinate u (the
// mapping inverted), and the nodes around u (count - 1) are blended: multilinearly (2 per axis,
// what a GPU's linear filter does with texel coordinate u (count - 1) + 0.5) or by Catmull–Rom
// (4 per axis). Coordinates outside an axis are clamped to its ends. The returned error is the
// same blend of the stored per-node errors with |weights|: how far the lookup is from blending
// the exact node values. It does NOT include the interpolation error between nodes, which
// Table::lookup_error (validated at bake time) does.
#pragma once

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

/// The table's axis coordinates of the law's coordinates x (identity for the cosines frame;
/// (theta_j, psi, beta) or (theta_j, offset, beta) of tables/frame.h for the lobe and warped frames).
std::vector<double> axis_coordinates(const Table& table, std::span<const double> x) noexcept;

/// Nodes and weights of one axis of a lookup at index coordinate u: `taps` nodes (2 linear, 4
/// Catmull–Rom) at node[k] with weight[k]; the weights sum to 1. Catmull–Rom's missing node
/// beyond an axis end is the even reflection for azimuths (phi, beta: the laws are even there)
/// and the quadratic extrapolation 3 p0 - 3 p1 + p2 otherwise, folded into the real nodes.
struct AxisTaps {
  int taps = 2;
  std::array<int, 4> node{};
  std::array<double, 4> weight{};
};
/// With `rounding`, the weights are those of a hardware filter with 8-bit sub-texel precision:
/// linear's t, and Catmull–Rom's fraction w2 / (w1 + w2) of its middle linear fetch, rounded to
/// a multiple of 1/256 (to nearest or down).
AxisTaps axis_taps(const Axis& axis, double u, Interpolation interpolation,
                   WeightRounding rounding = WeightRounding::exact) noexcept;
/// t rounded to a multiple of 1/kFilterWeightSteps as `rounding` says (exact: t itself).
double filter_weight(double t, WeightRounding rounding) noexcept;
/// Whether an axis is an azimuth about which the law is even (Catmull–Rom reflects there).
bool is_even_axis(const Axis& axis) noexcept;

/// The axis coordinates of directions i, j (local frame, n = +z; need not be unit) for the
/// table's law: g -> (i·n, j·n, relative azimuth in [0, pi]); h -> (j·n); a -> (i·n).
/// The relative azimuth of a direction along ±n is taken as 0 (the laws do not depend on it).
std::vector<double> coordinates(Law law, const Vec3& i, const Vec3& j) noexcept;

/// sample(table, coordinates(table.law, i, j)).
Sample sample(const Table& table, const Vec3& i, const Vec3& j, WeightRounding rounding = WeightRounding::exact) noexcept;

/// The lookup the table's bound is for: its filter's (hardware: 8-bit weights rounded to nearest,
/// as `ganzfeld sample --hardware-filter` does; texel_fetch: exact).
WeightRounding own_rounding(const Table& table) noexcept;

}  // namespace ganzfeld::tables
