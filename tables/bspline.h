// The interpolating cubic B-spline of b-spline tables (docs/lut-format.md, "Sampling", version 6).
// Along an axis of `count` entries the table stores the coefficients c_0 .. c_{count-1} of
//   S(s) = sum_k c_k B(s - k),   s = 1 + u (count - 3)
// (B the uniform cubic B-spline, u the axis' index coordinate), so the law is known at the count - 2
// nodes u = m / (count - 3), m = 0 .. count - 3, which sit at s = 1 .. count - 2; c_0 and c_{count-1}
// lie one step beyond the ends, so every lookup blends 4 stored coefficients with weights >= 0 and
// a hardware filter reads them as two linear fetches per axis (Sigg & Hadwiger, "Fast third-order
// texture filtering", GPU Gems 2, ch. 20). The baker solves for c so that S passes through the law
// at every node (Unser, "Splines: a perfect fit for signal and image processing", IEEE Signal
// Processing Magazine 16(6), 1999: (c_{k-1} + 4 c_k + c_{k+1}) / 6 = the node value), with two end
// conditions per axis line:
//   an azimuth (the laws are even there): c_0 = c_2 and c_{count-1} = c_{count-3} (S' = 0);
//   any other axis: S'' at the end node equals the one-sided difference 2 f_0 - 5 f_1 + 4 f_2 - f_3
//   of the node values (exact for cubics), i.e. c_0 - 2 c_1 + c_2 = that, and the same at the far end.
// Both reproduce cubics exactly (the spline then is the cubic); the error falls as h^4 up to the ends.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "tables/table.h"

namespace ganzfeld::tables {

/// The nodes of a b-spline axis where the law is computed: count - 2, at index coordinates
/// u = m / (count - 3) (axis.coordinate of those).
std::vector<double> bspline_nodes(const Axis& axis);

/// The coefficients (one per entry of `axes`, entry index as Table::value) of the spline through
/// `values`, given at the bspline_nodes of every axis (count - 2 per axis, the same order), and an
/// error bound for each: the lookup blends coefficients with weights >= 0 summing to 1, and the
/// spline moves by at most L times the largest change of a node value (L the product over the axes
/// of the interpolation's Lebesgue constant, ~1.5 to 2 per axis, computed for each axis' length and
/// end condition), so every coefficient's error is L times the largest of `errors` (the node
/// values' errors, same layout as `values`). With `first_axis_scale` (a function > 0 of the first
/// axis' coordinate that the lookup multiplies the spline by: a warped table's envelope A(theta_j),
/// docs/lut-format.md), the bound is for the scaled lookup: E = the largest error times the scale
/// at its node, coefficient k along the first axis is charged to its node (k - 1, clamped to the
/// ends) with error L E / scale there, and the first axis' constant is the least for which the
/// lookup's blend of those errors times the scale at the point bounds the scaled spline's move
/// everywhere. Axes need >= kBSplineMinCount entries.
struct Coefficients {
  std::vector<double> value, error;
};
Coefficients bspline_coefficients(std::span<const Axis> axes, const std::vector<double>& values,
                                  const std::vector<double>& errors,
                                  const std::function<double(double)>& first_axis_scale = nullptr);

/// The spline of a b-spline table at its nodes (the law there, up to the nodes' errors), laid out
/// as the input of bspline_coefficients (count - 2 per axis).
std::vector<double> bspline_node_values(const Table& table);

}  // namespace ganzfeld::tables
