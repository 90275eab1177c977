// Arctangent and arccosine for code that runs once per pixel (table lookups: tables/sample.cpp,
// tables/frame.cpp): within a few units in the last place of glibc's atan2 and acos, at the cost of
// one division and a degree-7 polynomial. Every lookup of a table — bake validation, `sample`, the
// rasterizer, `serve` — goes through the same functions, so the lookup a table's bound was validated
// for is the lookup the renderer performs.
#pragma once

#include <cmath>
#include <numbers>

namespace ganzfeld::util {

/// atan2(y, x) in [-pi, pi] with IEEE's signs of zero; within 1e-15 of the angle, relative. Reduction:
/// t = min(|x|, |y|) / max(|x|, |y|) in [0, 1]; above tan(pi/12), atan t = pi/6 + atan t' with
/// t' = (sqrt(3) t - 1) / (t + sqrt(3)) in [0, tan(pi/12)]; there atan t = t + t s P(s), s = t^2,
/// P of degree 7 fitted by least squares to the series (atan t - t)/(t s) (relative error of atan t
/// at most 2.3e-16 on the interval). Zeros, infinities and NaN go to std::atan2.
inline double atan2_fast(double y, double x) noexcept {
  const double ax = std::abs(x), ay = std::abs(y);
  if (!(ax < HUGE_VAL && ay < HUGE_VAL) || (ax == 0.0 && ay == 0.0)) return std::atan2(y, x);
  const bool steep = ay > ax;
  constexpr double kTanPi12 = 0.2679491924311227, kSqrt3 = std::numbers::sqrt3;
  // One division for both the ratio and the reduction: t = small / big, or
  // (sqrt(3) small - big) / (small + sqrt(3) big).
  const double small = steep ? ax : ay, big = steep ? ay : ax;
  const bool reduce = small > kTanPi12 * big;
  const double t = (reduce ? kSqrt3 * small - big : small) / (reduce ? small + kSqrt3 * big : big);
  const double base = reduce ? std::numbers::pi / 6.0 : 0.0;
  const double s = t * t;
  // Estrin's scheme (depth 3 instead of Horner's 7: the chain of dependent multiply-adds is what a
  // lookup waits for).
  const double s2 = s * s, s4 = s2 * s2;
  const double p =
      (-0.33333333333333365 + s * 0.19999999999842255) + s2 * (-0.1428571423944038 + s * 0.11111105930515412) +
      s4 * ((-0.09090623405398705 + s * 0.07683707269840619) + s2 * (-0.06521723544410353 + s * 0.045770883301051224));
  double angle = base + (t + t * s * p);
  angle = steep ? std::numbers::pi / 2.0 - angle : angle;
  angle = x < 0.0 ? std::numbers::pi - angle : angle;
  return std::copysign(angle, y);
}

/// acos(c) for c in [-1, 1] as atan2_fast(sqrt((1 - c)(1 + c)), c): the product keeps the sine's
/// relative accuracy near c = +-1, where 1 - c c would cancel. Outside [-1, 1] or NaN: std::acos.
inline double acos_fast(double c) noexcept {
  if (!(c >= -1.0 && c <= 1.0)) return std::acos(c);
  return atan2_fast(std::sqrt((1.0 - c) * (1.0 + c)), c);
}

}  // namespace ganzfeld::util
