#include "tables/bspline.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>

#include "tables/sample.h"

namespace ganzfeld::tables {

namespace {

/// The coefficients c_0 .. c_{n+1} of one line through the n >= 4 node values f (tables/bspline.h):
/// rows (c_{m} + 4 c_{m+1} + c_{m+2}) / 6 = f_m for m = 0 .. n-1 and the two end conditions, solved
/// by Thomas's algorithm on the rows in c_1 .. c_n after eliminating c_0 and c_{n+1} (the matrix
/// stays strictly diagonally dominant, so no pivoting).
std::vector<double> solve_line(const std::vector<double>& f, bool even) {
  const std::size_t n = f.size();
  std::vector<double> c(n + 2, 0.0), diag(n, 4.0), lower(n, 1.0), upper(n, 1.0), rhs(n);
  for (std::size_t m = 0; m < n; ++m) rhs[m] = 6.0 * f[m];
  double d2_first = 0.0, d2_last = 0.0;
  if (even) {  // c_0 = c_2: row 0 is 4 c_1 + 2 c_2; the same at the far end
    upper[0] = 2.0;
    lower[n - 1] = 2.0;
  } else {  // c_0 = d2 + 2 c_1 - c_2: row 0 is 6 c_1 = 6 f_0 - d2
    d2_first = 2.0 * f[0] - 5.0 * f[1] + 4.0 * f[2] - f[3];
    d2_last = 2.0 * f[n - 1] - 5.0 * f[n - 2] + 4.0 * f[n - 3] - f[n - 4];
    diag[0] = 6.0;
    upper[0] = 0.0;
    rhs[0] -= d2_first;
    diag[n - 1] = 6.0;
    lower[n - 1] = 0.0;
    rhs[n - 1] -= d2_last;
  }
  lower[0] = 0.0;
  upper[n - 1] = 0.0;
  std::vector<double> u(n);
  double denominator = diag[0];
  u[0] = upper[0] / denominator;
  rhs[0] /= denominator;
  for (std::size_t m = 1; m < n; ++m) {
    denominator = diag[m] - lower[m] * u[m - 1];
    u[m] = upper[m] / denominator;
    rhs[m] = (rhs[m] - lower[m] * rhs[m - 1]) / denominator;
  }
  for (std::size_t m = n - 1; m-- > 0;) rhs[m] -= u[m] * rhs[m + 1];
  for (std::size_t m = 0; m < n; ++m) c[m + 1] = rhs[m];
  c[0] = even ? c[2] : d2_first + 2.0 * c[1] - c[2];
  c[n + 1] = even ? c[n - 1] : d2_last + 2.0 * c[n] - c[n - 1];
  return c;
}

/// The uniform cubic B-spline B(x) (support [-2, 2]).
double cubic_bspline(double x) {
  const double a = std::abs(x);
  if (a >= 2.0) return 0.0;
  if (a >= 1.0) return (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
  return (4.0 - 6.0 * a * a + 3.0 * a * a * a) / 6.0;
}

/// The Lebesgue constant of a line of n nodes: max over s in [1, n] of sum_m |dS(s)/df_m|, S the
/// spline through the node values f. The solve is linear, so dS/df_m is the spline of the m-th unit
/// vector; the maximum is taken at kLebesgueSamples points per cell (the Lebesgue function is
/// smooth inside a cell, so the sampled maximum is within a fraction of a percent of the true one;
/// kLebesgueSlack covers the rest). With the scale at the nodes (the factor the lookup multiplies
/// by; node m sits at s = m + 1, and coefficient k is charged to node clamp(k, 1, n) - 1): max over
/// s of [sum_m |dS(s)/df_m| / scale_m] / [sum_k B(s - k) / scale at the node of k], so that
/// coefficient errors G E / scale at the node of k, blended by the lookup's weights B(s - k) and
/// multiplied by the scale at s, bound the scaled |dS| at every s for node errors E / scale_m (the
/// scale at s cancels). An empty node_scale is 1 everywhere.
constexpr int kLebesgueSamples = 64;
constexpr double kLebesgueSlack = 1.01;
double lebesgue_constant(std::size_t n, bool even, std::span<const double> node_scale) {
  auto scale = [&](std::size_t m) { return node_scale.empty() ? 1.0 : node_scale[m]; };
  std::vector<std::vector<double>> columns;
  std::vector<double> unit(n, 0.0);
  for (std::size_t m = 0; m < n; ++m) {
    unit.assign(n, 0.0);
    unit[m] = 1.0;
    columns.push_back(solve_line(unit, even));
  }
  double largest = 0.0;
  for (std::size_t cell = 1; cell < n; ++cell)
    for (int p = 0; p <= kLebesgueSamples; ++p) {
      const double s = static_cast<double>(cell) + static_cast<double>(p) / kLebesgueSamples;
      double sum = 0.0, charged = 0.0;
      for (std::size_t k = cell - 1; k <= cell + 2 && k < n + 2; ++k)
        charged += cubic_bspline(s - k) / scale(std::clamp<std::size_t>(k, 1, n) - 1);
      for (std::size_t m = 0; m < n; ++m) {
        double at = 0.0;
        for (std::size_t k = cell - 1; k <= cell + 2 && k < n + 2; ++k) at += columns[m][k] * cubic_bspline(s - k);
        sum += std::abs(at) / scale(m);
      }
      largest = std::max(largest, sum / charged);
    }
  return largest * kLebesgueSlack;
}

/// Replaces every line along axis d of the grid `values` (entry index slowest axis first, `shape`
/// entries per axis) by `map` of it, a line of `length` entries; shape[d] becomes `length`.
template <class Map>
std::vector<double> map_lines(const std::vector<double>& values, std::vector<std::size_t>& shape, std::size_t d,
                              std::size_t length, Map&& map) {
  const std::size_t n = shape[d];
  std::size_t outer = 1, inner = 1;
  for (std::size_t e = 0; e < d; ++e) outer *= shape[e];
  for (std::size_t e = d + 1; e < shape.size(); ++e) inner *= shape[e];
  std::vector<double> next(outer * length * inner), line(n);
  for (std::size_t o = 0; o < outer; ++o)
    for (std::size_t i = 0; i < inner; ++i) {
      for (std::size_t m = 0; m < n; ++m) line[m] = values[(o * n + m) * inner + i];
      const std::vector<double> mapped = map(line);
      for (std::size_t k = 0; k < length; ++k) next[(o * length + k) * inner + i] = mapped[k];
    }
  shape[d] = length;
  return next;
}

}  // namespace

std::vector<double> bspline_nodes(const Axis& axis) {
  const int n = axis.count - 2;
  std::vector<double> x(static_cast<std::size_t>(std::max(n, 0)));
  for (int m = 0; m < n; ++m) x[m] = m + 1 == n ? axis.max : axis.coordinate(static_cast<double>(m) / (n - 1));
  if (n > 0) x[0] = axis.min;
  return x;
}

Coefficients bspline_coefficients(std::span<const Axis> axes, const std::vector<double>& values,
                                  const std::vector<double>& errors,
                                  const std::function<double(double)>& first_axis_scale) {
  // Axis by axis, the grid grows from count - 2 to count entries along it.
  std::vector<std::size_t> shape;
  for (const Axis& a : axes) shape.push_back(static_cast<std::size_t>(a.count - 2));
  // The scale at the first axis' nodes (bspline_nodes: node m at index coordinate m / (first - 1)).
  const std::size_t first = shape[0];
  std::vector<double> node_scale(first_axis_scale ? first : 0);
  for (std::size_t m = 0; m < node_scale.size(); ++m)
    node_scale[m] = first_axis_scale(axes[0].coordinate(static_cast<double>(m) / (first - 1.0)));
  auto scale = [&](std::size_t m) { return node_scale.empty() ? 1.0 : node_scale[m]; };
  std::vector<double> c = values;
  double gain = 1.0;
  for (std::size_t d = 0; d < axes.size(); ++d) {
    const bool even = is_even_axis(axes[d]);
    gain *= lebesgue_constant(shape[d], even, d == 0 ? std::span<const double>(node_scale) : std::span<const double>());
    c = map_lines(c, shape, d, shape[d] + 2, [&](const std::vector<double>& line) { return solve_line(line, even); });
  }
  // The nodes' largest error in the scaled units; a coefficient's bound in the stored units is
  // that times the gain over the scale at its node (the first axis' coefficient k at node k - 1).
  const std::size_t plane = errors.size() / first;
  double worst = 0.0;
  for (std::size_t m = 0; m < errors.size(); ++m) worst = std::max(worst, errors[m] * scale(m / plane));
  std::vector<double> error(c.size());
  const std::size_t coefficient_plane = c.size() / (first + 2);
  for (std::size_t m = 0; m < c.size(); ++m)
    error[m] = gain * worst / scale(std::clamp<std::size_t>(m / coefficient_plane, 1, first) - 1);
  return {std::move(c), std::move(error)};
}

std::vector<double> bspline_node_values(const Table& table) {
  std::vector<std::size_t> shape;
  for (const Axis& a : table.axes) shape.push_back(static_cast<std::size_t>(a.count));
  std::vector<double> v(table.value.begin(), table.value.end());
  for (std::size_t d = 0; d < shape.size(); ++d)
    v = map_lines(v, shape, d, shape[d] - 2, [](const std::vector<double>& c) {
      std::vector<double> at_nodes(c.size() - 2);
      for (std::size_t m = 0; m < at_nodes.size(); ++m) at_nodes[m] = (c[m] + 4.0 * c[m + 1] + c[m + 2]) / 6.0;
      return at_nodes;
    });
  return v;
}

}  // namespace ganzfeld::tables
