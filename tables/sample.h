// Table lookup: per axis, invert the mapping to the index coordinate u, then interpolate
// linearly in index space between the two neighbouring nodes (multilinear over the axes), which
// is what a GPU's linear filter does with texel coordinate u (count - 1) + 0.5. Coordinates
// outside an axis are clamped to its ends. The returned error is the same interpolation of the
// stored per-node errors: a bound on how far the interpolated value is from interpolating the
// exact node values. It does NOT include the interpolation (discretization) error between nodes.
#pragma once

#include <span>
#include <vector>

#include "laws/model.h"
#include "tables/table.h"

namespace ganzfeld::tables {

struct Sample {
  double value = 0.0;
  double error = 0.0;
};

/// Lookup at axis coordinates x[d] (one per axis, in the axes' own units).
Sample sample(const Table& table, std::span<const double> x) noexcept;

/// The axis coordinates of directions i, j (local frame, n = +z; need not be unit) for the
/// table's law: g -> (i·n, j·n, relative azimuth in [0, pi]); h -> (j·n); a -> (i·n).
/// The relative azimuth of a direction along ±n is taken as 0 (the laws do not depend on it).
std::vector<double> coordinates(Law law, const Vec3& i, const Vec3& j) noexcept;

/// sample(table, coordinates(table.law, i, j)).
Sample sample(const Table& table, const Vec3& i, const Vec3& j) noexcept;

}  // namespace ganzfeld::tables
