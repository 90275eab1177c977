// The helpers the models' GLSL f call (models/glsl.h), each written once.
#include "models/glsl.h"

#include <set>
#include <stdexcept>

namespace ganzfeld {

namespace {

struct Helper {
  const char* name;
  std::vector<const char*> needs;  ///< helpers it calls
  const char* code;
};

// Dependencies come before their users in this list, which is also the emission order.
const std::vector<Helper>& helpers() {
  static const std::vector<Helper> list = {
      {"gz_frame",
       {},
       R"(// World to the local frame of a BRDF: z the unit normal n, x the part of the tangent t across n
// (t any vector not along n), y = n x x (models/model.h: n = +z, the tangent = +x).
vec3 gz_to_local(vec3 v, vec3 n, vec3 t) {
  vec3 x = normalize(t - dot(t, n) * n), y = cross(n, x);
  return vec3(dot(v, x), dot(v, y), dot(v, n));
}
// A tangent for an isotropic BRDF, where any will do: a world axis far from n.
vec3 gz_any_tangent(vec3 n) { return abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0); }
// The tangent of a scene object's "tangent" rule (scene/scene.h, brush_tangent): along the circles
// of latitude about `axis` (axis x n) or along its meridians (axis minus its part along n); where n
// lies along the axis, gz_any_tangent.
vec3 gz_brush_tangent(vec3 n, vec3 axis, bool latitude) {
  vec3 t = latitude ? cross(axis, n) : axis - dot(axis, n) * n;
  return dot(t, t) > 1e-12 * dot(axis, axis) ? normalize(t) : gz_any_tangent(n);
}
)"},
      {"gz_log1p",
       {},
       R"(// log(1 + x) to float precision near 0, where log(1.0 + x) loses x: 2 atanh(s), s = x/(2 + x),
// by its series (|s| < 0.143 for |x| < 1/4: the terms beyond s^13 are below 2^-24 of the sum).
float gz_log1p(float x) {
  if (abs(x) >= 0.25) return log(1.0 + x);
  float s = x / (2.0 + x), z = s * s;
  return 2.0 * s * (1.0 + z * (0.333333333 + z * (0.2 + z * (0.142857143 + z * (0.111111111 + z * (0.0909090909
         + z * 0.0769230769))))));
}
)"},
      {"gz_pow1m",
       {"gz_log1p"},
       R"(// (1 - y)^n for y in [0, 1] (0 for y >= 1, 1 for y <= 0), accurate when y is small: a sharp lobe
// near its peak, where pow(1.0 - y, n) would round 1 - y first and err by n ulps.
float gz_pow1m(float y, float n) {
  if (y >= 1.0) return 0.0;
  if (y <= 0.0) return 1.0;
  return exp(n * gz_log1p(-y));
}
)"},
      {"gz_pow_pair",
       {"gz_pow1m"},
       R"(// x^n from x and y = 1 - x, each computed without cancellation: from whichever is the smaller,
// so the power is accurate both near x = 1 (a sharp lobe's peak) and near x = 0. 0 for x <= 0.
float gz_pow_pair(float x, float y, float n) {
  if (x <= 0.0) return 0.0;
  return x < 0.5 ? pow(x, n) : gz_pow1m(y, n);
}
)"},
      {"gz_mirror_power",
       {"gz_pow_pair"},
       R"(// max(0, k.j)^n with k = (-i.x, -i.y, i.z) the mirror direction of i (models/classic.cpp,
// cosine_power); 1 - k.j = |k - j|^2/2 for unit k, j.
float gz_mirror_power(vec3 i, vec3 j, float n) {
  vec3 k = vec3(-i.x, -i.y, i.z), d = k - j;
  return gz_pow_pair(dot(k, j), 0.5 * dot(d, d), n);
}
)"},
      {"gz_half_cos_power",
       {"gz_pow_pair"},
       R"(// ((1 + u.v)/2)^n for unit u, v, from |u + v|^2/4 and 1 minus it, |u - v|^2/4 (K&P's lobes).
float gz_half_cos_power(vec3 u, vec3 v, float n) {
  vec3 s = u + v, d = u - v;
  return gz_pow_pair(0.25 * dot(s, s), 0.25 * dot(d, d), n);
}
)"},
      {"gz_expm1",
       {},
       R"(// exp(x) - 1 to float precision near 0: its Taylor series for |x| < 1/2 (the terms beyond x^9/9!
// are below 2^-24 of the sum), exp(x) - 1 beyond.
float gz_expm1(float x) {
  if (abs(x) >= 0.5) return exp(x) - 1.0;
  return x * (1.0 + x * (0.5 + x * (0.166666667 + x * (0.0416666667 + x * (0.00833333333 + x * (0.00138888889
         + x * (1.98412698e-4 + x * (2.48015873e-5 + x * 2.75573192e-6))))))));
}
)"},
      {"gz_asin",
       {},
       R"(// asin(x), Cephes' asinf kernel (relative error ~2e-7): GLSL leaves asin's accuracy unspecified.
float gz_asin(float x) {
  float a = abs(x);
  bool reduce = a > 0.5;                  // asin(a) = pi/2 - 2 asin(sqrt((1 - a)/2))
  float z = reduce ? 0.5 * (1.0 - a) : a * a;
  float s = reduce ? sqrt(z) : a;
  float p = ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z + 7.4953002686e-2) * z
             + 1.6666752422e-1) * z * s + s;
  if (reduce) p = 1.5707963268 - 2.0 * p;
  return x < 0.0 ? -p : p;
}
)"},
      {"gz_acos",
       {"gz_asin"},
       R"(// acos(x), Cephes' acosf: from asin of the half-angle near +-1, where acos is ill-conditioned.
float gz_acos(float x) {
  x = clamp(x, -1.0, 1.0);
  if (x < -0.5) return 3.1415926536 - 2.0 * gz_asin(sqrt(0.5 * (1.0 + x)));
  if (x > 0.5) return 2.0 * gz_asin(sqrt(0.5 * (1.0 - x)));
  return 1.5707963268 - gz_asin(x);
}
)"},
      {"gz_atan2",
       {},
       R"(// atan2(y, x) in [-pi, pi] (0 for 0, 0), Cephes' atanf kernel on the ratio of the smaller to the
// larger magnitude (relative error ~2e-7): GLSL leaves atan's accuracy unspecified.
float gz_atan2(float y, float x) {
  float a = abs(y), b = abs(x), big = max(a, b);
  if (big == 0.0) return 0.0;
  float r = min(a, b) / big;
  bool reduce = r > 0.4142135624;         // atan(r) = pi/4 + atan((r - 1)/(r + 1))
  float t = reduce ? (r - 1.0) / (r + 1.0) : r;
  float z = t * t;
  float p = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * t + t;
  if (reduce) p += 0.7853981634;
  if (a > b) p = 1.5707963268 - p;
  if (x < 0.0) p = 3.1415926536 - p;
  return y < 0.0 ? -p : p;
}
)"},
      {"gz_erfc",
       {},
       R"(// erfc(x): Numerical Recipes' erfcc, a Chebyshev fit with fractional error < 1.2e-7 everywhere
// (Press et al., Numerical Recipes in C, 2nd ed., section 6.2).
float gz_erfc(float x) {
  float z = abs(x), t = 1.0 / (1.0 + 0.5 * z);
  float r = t * exp(-z * z - 1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806
            + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))));
  return x >= 0.0 ? r : 2.0 - r;
}
)"},
      {"gz_schlick",
       {},
       R"(// Schlick's Fresnel F_0 + (F_90 - F_0)(1 - cos)^5 (models/hvd.h, hvd::schlick).
float gz_schlick(float cos_theta, float F_0, float F_90) {
  float x = 1.0 - clamp(cos_theta, 0.0, 1.0), x2 = x * x;
  return F_0 + (F_90 - F_0) * x2 * x2 * x;
}
)"},
      {"gz_hvd_lump",
       {"gz_pow_pair"},
       R"(// The elliptical lump of Edwards et al. eq. 27 at disk point h (models/hvd.h, hvd::Lump::pdf):
// (n + 1)/(pi R_u R_v) (1 - |(h - centre)/R|^2)^n inside the ellipse, 0 outside.
float gz_hvd_lump(vec2 h, vec2 centre, vec2 R, float n) {
  vec2 d = (h - centre) / R;
  float y = dot(d, d);
  if (!(y < 1.0)) return 0.0;
  return (n + 1.0) / (3.1415926536 * R.x * R.y) * gz_pow_pair(1.0 - y, y, n);
}
)"},
      {"gz_one_minus_schlick",
       {},
       R"(// 1 - Schlick's F = (1 - F_90) x^5 + (1 - F_0)(1 - x^5), x = 1 - cos, with 1 - x^5 = cos (1 + x + x^2
// + x^3 + x^4): no cancellation at grazing, where F -> F_90 = 1 (the diffuse weight of models/hvd.cpp).
float gz_one_minus_schlick(float cos_theta, float F_0, float F_90) {
  float c = clamp(cos_theta, 0.0, 1.0), x = 1.0 - c, x2 = x * x;
  return (1.0 - F_90) * x2 * x2 * x + (1.0 - F_0) * c * (1.0 + x + x2 + x2 * x + x2 * x2);
}
)"},
      {"gz_lambert_sphere_bracket",
       {"gz_atan2"},
       R"(// sin d - d cos d, d = pi - alpha the supplement of the angle between unit u and v, from
// d = 2 atan2(|u + v|, |u - v|) and by its series below d = 0.1, where the terms cancel to d^3/3
// (models/blinn_dusty.cpp, lambert_sphere_bracket): the Lambert-sphere phase law's bracket.
float gz_lambert_sphere_bracket(vec3 u, vec3 v) {
  float d = 2.0 * gz_atan2(length(u + v), length(u - v)), d2 = d * d;
  if (d >= 0.1) return max(0.0, sin(d) - d * cos(d));
  return d * d2 * (0.333333333 - d2 * (0.0333333333 - d2 * (0.00119047619 - d2 * 2.20458554e-5)));
}
)"},
      {"gz_he_series_over_g",
       {"gz_log1p"},
       R"(// He-Torrance's series of eq. 78 divided by g (models/he_torrance.h, he_series_over_g):
//   T(g, c) = sum_{m>=1} t_m, t_m = e^{-g} g^{m-1}/m! e^{-c/m}/m,   c >= 0,
// in float: from the largest term outwards. t_{m+1}/t_m = g m e^{c/(m (m+1))}/(m+1)^2 decreases
// with m (the terms are log-concave), so the peak is where that ratio crosses 1 (bisection) and
// each side's tail after a term t with ratio r < 1 is below t r/(1 - r): summed until that is
// below 2^-26 of the sum. The peak's size from the Poisson weight in Stirling's form,
// ln(e^{-g} g^m/m!) = -(m ln(m/g) - m + g) - ln(2 pi m)/2 - s(m), m ln(m/g) - m + g = g
// ((1 + u) ln(1 + u) - u), u = (m - g)/g (no cancellation of g against m ln g), s(m) the Stirling
// correction (exact below 8, 1/(12m) - 1/(360m^3) + 1/(1260m^5) from 8).
float gz_he_log_ratio(float g, float c, float m) {
  return log(g) + log(m) - 2.0 * log(m + 1.0) + c / (m * (m + 1.0));
}
float gz_he_series_over_g(float g, float c) {
  if (!(g > 0.0)) return exp(-c);
  float lo = 1.0, hi = 2.0;
  if (gz_he_log_ratio(g, c, 1.0) <= 0.0) {
    hi = 1.0;
  } else {
    for (int k = 0; k < 64 && gz_he_log_ratio(g, c, hi) > 0.0; ++k) { lo = hi; hi *= 2.0; }
    for (int k = 0; k < 60; ++k) {
      float mid = 0.5 * (lo + hi);
      if (gz_he_log_ratio(g, c, mid) > 0.0) lo = mid; else hi = mid;
    }
  }
  float m0 = max(1.0, ceil(hi));  // the first m whose ratio is below 1: the largest term
  float u = (m0 - g) / g;
  float D = g * ((1.0 + u) * gz_log1p(u) - u);
  float s = m0 < 8.0 ? (m0 < 2.0 ? 0.0810614668 : m0 < 3.0 ? 0.041340696 : m0 < 4.0 ? 0.0276779257 : m0 < 5.0
            ? 0.0207906721 : m0 < 6.0 ? 0.0166446912 : m0 < 7.0 ? 0.0138761288 : 0.0118967099)
            : (1.0 / 12.0 - (1.0 / 360.0 - 1.0 / (1260.0 * m0 * m0)) / (m0 * m0)) / m0;
  float log_peak = -D - 0.5 * log(6.2831853072 * m0) - s - log(g) - c / m0 - log(m0);
  float sum = 1.0, t = 1.0;
  for (float m = m0; m < m0 + 1e6; m += 1.0) {  // upwards: t_{m+1} = t_m r_m
    float r = exp(gz_he_log_ratio(g, c, m));
    t *= r;
    sum += t;
    if (r < 1.0 && t * r / (1.0 - r) <= 1.4901161e-8 * sum) break;
  }
  t = 1.0;
  for (float m = m0 - 1.0; m >= 1.0; m -= 1.0) {  // downwards: t_m = t_{m+1} / r_m
    float q = exp(-gz_he_log_ratio(g, c, m));
    t *= q;
    sum += t;
    if (q < 1.0 && t * q / (1.0 - q) <= 1.4901161e-8 * sum) break;
  }
  return exp(log_peak) * sum;
}
)"},
      {"gz_he_terms",
       {"gz_erfc"},
       R"(// He-Torrance (models/he_torrance.h): eq. 82-83's K = tan theta erfc(tau cot theta/(2 sigma0))
// (+inf on the horizon: the caller handles mu = 0), S(theta)/cos theta of eq. 24-25 with Smith's
// exp(-a^2) computed without dividing by cos theta, and z0/sigma0 of eq. 81 by safeguarded Newton
// on ln x + x^2/2 = ln f0 (HeTorrance::K, shadowing_over_cos, he_z0_over_sigma0).
float gz_he_K(float mu, float sin_theta, float tau, float sigma0) {
  if (!(sin_theta > 0.0)) return 0.0;
  return sin_theta / mu * gz_erfc(tau * mu / (2.0 * sigma0 * sin_theta));
}
float gz_he_shadowing_over_cos(float mu, float sin_theta, float tau, float sigma0) {
  if (!(sin_theta > 0.0)) return mu > 0.0 ? 1.0 / mu : 0.0;
  float b = tau / (2.0 * sigma0 * sin_theta), a = b * mu;
  if (a > 27.0) return 1.0 / mu;
  float e = gz_erfc(a);
  return (1.0 - 0.5 * e) * b / (a + 0.5 * (exp(-a * a) * 0.5641895835 - a * e));
}
float gz_he_z0_over_sigma0(float f0) {
  if (!(f0 > 0.0)) return 0.0;
  float L = log(f0), lo, hi, x;
  if (f0 <= 1.0) {
    lo = f0 * 0.6065306597; hi = f0; x = f0;
  } else {
    lo = sqrt(L); hi = max(1.0, sqrt(2.0 * L)); x = clamp(sqrt(2.0 * L), lo, hi);
  }
  for (int it = 0; it < 60; ++it) {
    float psi = log(x) + 0.5 * x * x - L;
    if (psi == 0.0) return x;
    if (psi > 0.0) hi = x; else lo = x;
    float next = x - psi / (1.0 / x + x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (abs(next - x) <= 1.2e-7 * x) return next;
    x = next;
  }
  return x;
}
)"},
      {"gz_cos_power_integral",
       {"gz_pow1m"},
       R"(// The integral of cos^m t from t_a to t_b, -pi/2 <= t_a <= t_b <= pi/2, m >= 0 real
// (models/poulin_fournier.h, cos_power_integral): by incomplete beta functions, the integral from
// 0 to tau being B(sin^2 tau; 1/2, (m+1)/2)/2 and from tau to pi/2 B(cos^2 tau; (m+1)/2, 1/2)/2,
// each from Numerical Recipes' continued fraction (Press et al., 2nd ed., section 6.4, betacf) on
// the side where it converges, and the complete B(1/2, b) = sqrt(pi) Gamma(b)/Gamma(b + 1/2) from
// its asymptotic series beyond b = 10 (no lgamma cancellation in float); heads below the median of
// cos^m (0.6745/sqrt(m)), tails above, as the CPU.
float gz_betacf(float a, float b, float x) {
  float qab = a + b, qap = a + 1.0, qam = a - 1.0, c = 1.0, d = 1.0 - qab * x / qap;
  if (abs(d) < 1e-30) d = 1e-30;
  d = 1.0 / d;
  float h = d;
  for (int k = 1; k <= 400; ++k) {
    float m = float(k), m2 = 2.0 * m;
    float aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d; if (abs(d) < 1e-30) d = 1e-30;
    c = 1.0 + aa / c; if (abs(c) < 1e-30) c = 1e-30;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d; if (abs(d) < 1e-30) d = 1e-30;
    c = 1.0 + aa / c; if (abs(c) < 1e-30) c = 1e-30;
    d = 1.0 / d;
    float del = d * c;
    h *= del;
    if (abs(del - 1.0) < 6e-8) break;
  }
  return h;
}
// B(1/2, b) = sqrt(pi) Gamma(b)/Gamma(b + 1/2): b raised past 10 by Gamma(b + 1) = b Gamma(b), then
// the asymptotic series of Gamma(b)/Gamma(b + 1/2) (its next term is below 2e-8 there).
float gz_beta_half(float b) {
  float factor = 1.0;
  for (int k = 0; k < 10 && b < 10.0; ++k) { factor *= (b + 0.5) / b; b += 1.0; }
  float r = 1.0 / b;
  return 1.7724538509 * factor * sqrt(r) * (1.0 + r * (0.125 + r * (0.0078125 + r * (-0.0048828125
         - r * 0.000640869141))));
}
// The integral of cos^m from 0 to tau (head) and from tau to pi/2 (tail), tau in [0, pi/2]:
// x^p (1 - x)^q / p times the fraction, with sin, cos of tau.
float gz_cos_power_head(float m, float s, float c) {
  c = max(c, 0.0);  // float's pi/2 lies beyond pi/2: its cosine is -4e-8, and pow of a negative is undefined
  float b = 0.5 * (m + 1.0), x = s * s;
  if (x < 1.5 / (b + 2.5)) return 0.5 * (s * gz_pow1m(x, b) / 0.5) * gz_betacf(0.5, b, x);
  return 0.5 * (gz_beta_half(b) - pow(c, 2.0 * b) * s / b * gz_betacf(b, 0.5, c * c));
}
float gz_cos_power_tail(float m, float s, float c) {
  c = max(c, 0.0);  // as in gz_cos_power_head
  float b = 0.5 * (m + 1.0), x = c * c;
  if (x < (b + 1.0) / (b + 2.5)) return 0.5 * pow(c, 2.0 * b) * s / b * gz_betacf(b, 0.5, x);
  return 0.5 * (gz_beta_half(b) - s * gz_pow1m(s * s, b) / 0.5 * gz_betacf(0.5, b, s * s));
}
float gz_cos_power_integral(float m, float t_a, float t_b) {
  t_a = clamp(t_a, -1.5707963268, 1.5707963268);
  t_b = clamp(t_b, -1.5707963268, 1.5707963268);
  if (!(t_b > t_a)) return 0.0;
  float value;
  if (t_a < 0.0 && t_b > 0.0) {
    value = gz_cos_power_head(m, sin(-t_a), cos(t_a)) + gz_cos_power_head(m, sin(t_b), cos(t_b));
  } else {
    float lo = t_a >= 0.0 ? t_a : -t_b, hi = t_a >= 0.0 ? t_b : -t_a;
    float split = min(0.6745 / sqrt(max(m, 1.0)), 0.7853981634);
    value = hi <= split ? gz_cos_power_head(m, sin(hi), cos(hi)) - gz_cos_power_head(m, sin(lo), cos(lo))
                        : gz_cos_power_tail(m, sin(lo), cos(lo)) - gz_cos_power_tail(m, sin(hi), cos(hi));
  }
  return isinf(value) || isnan(value) || !(value > 0.0) ? 0.0 : value;
}
)"},
      {"gz_pf",
       {"gz_asin", "gz_atan2", "gz_pow1m", "gz_cos_power_integral"},
       R"(// Poulin-Fournier's cylinders (models/poulin_fournier.h, PoulinFournier): a direction's projection
// (side, elevation beta) on the cross-section, the neighbour's shadow line theta_s, the floor's
// blocked part f_s, a direction's front (arc_lo, arc_hi, floor_lo, floor_hi), and the two arc
// integrals, as the CPU computes them.
vec2 gz_pf_project(vec3 k) {
  return vec2(k.y >= 0.0 ? 1.0 : -1.0, clamp(gz_atan2(max(k.z, 0.0), abs(k.y)), 1e-6, 1.5707963268));
}
float gz_pf_neighbour_limit(float beta, float d) {
  float sb = sin(beta);
  if ((d - 1.0) * sb > 1.0) return 1.5707963268;
  return 2.0 * gz_asin(min(1.0, sqrt(0.5 * d * sb))) - beta;
}
float gz_pf_floor_blocked(float beta, float theta_M, float w) {
  if (!(w > 0.0) || beta >= theta_M) return 0.0;
  float s = sin(0.5 * (beta - theta_M));
  return min(2.0 * s * s / sin(beta), w);
}
vec4 gz_pf_front(vec2 p, float d, float theta_M, float w) {
  if (p.y >= theta_M) return vec4(-theta_M, theta_M, 0.0, w);
  float near = min(gz_pf_neighbour_limit(p.y, d), theta_M), far = p.y, blocked = gz_pf_floor_blocked(p.y, theta_M, w);
  return p.x > 0.0 ? vec4(-far, near, 0.0, w - blocked) : vec4(-near, far, blocked, w);
}
// (x - sin x cos x)/2 = (y - sin y)/4, y = 2x, by its series below y = 1.
float gz_pf_integral_sin_squared(float x) {
  float y = 2.0 * abs(x), v;
  if (y < 1.0) {
    float y2 = y * y;
    v = y * y2 * (0.166666667 - y2 * (0.00833333333 - y2 * (1.98412698e-4 - y2 * (2.75573192e-6 - y2 * 2.50521084e-8))))
        / 4.0;
  } else {
    v = (y - sin(y)) / 4.0;
  }
  return x < 0.0 ? -v : v;
}
float gz_pf_arc_cosine_product(vec2 pi_, vec2 pj, float a, float b) {
  if (!(b > a)) return 0.0;
  float value;
  if (pi_.x == pj.x) {
    float s = pi_.x, mid = 0.5 * (pi_.y + pj.y), h = sin(0.5 * (pi_.y - pj.y));
    value = abs(gz_pf_integral_sin_squared(s * b + mid) - gz_pf_integral_sin_squared(s * a + mid)) - h * h * (b - a);
  } else {
    float s = pi_.x, off = 0.5 * (pi_.y - pj.y), sum = sin(0.5 * (pi_.y + pj.y));
    value = sum * sum * (b - a)
            - abs(gz_pf_integral_sin_squared(s * b + off) - gz_pf_integral_sin_squared(s * a + off));
  }
  value /= sin(pi_.y) * sin(pj.y);
  return isinf(value) || isnan(value) || !(value > 0.0) ? 0.0 : value;
}
float gz_pf_arc_specular(vec2 pi_, vec2 pj, float a, float b, vec3 h, float n) {
  if (!(b > a)) return 0.0;
  float rn = gz_pow1m(h.x * h.x, 0.5 * n);  // r_h^n, r_h = |h_yz| = sqrt(1 - h_x^2)
  if (!(rn > 0.0)) return 0.0;
  float theta_H = gz_atan2(h.y, h.z);
  float P0, P1, P2;
  if (pi_.x == pj.x) {
    float S = pi_.y + pj.y;
    P0 = 0.5 * cos(pi_.y - pj.y); P1 = -0.5 * cos(S); P2 = 0.5 * pi_.x * sin(S);
  } else {
    float D = pi_.y - pj.y;
    P0 = -0.5 * cos(pi_.y + pj.y); P1 = 0.5 * cos(D); P2 = -0.5 * pi_.x * sin(D);
  }
  float c2 = cos(2.0 * theta_H), s2 = sin(2.0 * theta_H);
  float A = P0, B = P1 * c2 + P2 * s2, C = P2 * c2 - P1 * s2;
  float ta = clamp(a - theta_H, -1.5707963268, 1.5707963268), tb = clamp(b - theta_H, -1.5707963268, 1.5707963268);
  float sin_a = sin(ta), sin_b = sin(tb), cos_a = max(cos(ta), 0.0), cos_b = max(cos(tb), 0.0);
  float pow_a = gz_pow1m(sin_a * sin_a, 0.5 * (n + 1.0)), pow_b = gz_pow1m(sin_b * sin_b, 0.5 * (n + 1.0));
  float In = gz_cos_power_integral(n, ta, tb);
  float In2 = ((pow_b * sin_b - pow_a * sin_a) + (n + 1.0) * In) / (n + 2.0);
  float tail = 2.0 / (n + 2.0) * (pow_a * cos_a - pow_b * cos_b);
  float value = rn * ((A - B) * In + 2.0 * B * In2 + C * tail) / (sin(pi_.y) * sin(pj.y));
  return isinf(value) || isnan(value) || !(value > 0.0) ? 0.0 : value;
}
)"},
      {"gz_complex",
       {},
       R"(// Complex arithmetic on vec2 (x real, y imaginary).
vec2 gz_cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 gz_cdiv(vec2 a, vec2 b) { return gz_cmul(a, vec2(b.x, -b.y)) / dot(b, b); }
// The principal square root (real part >= 0, the imaginary part's sign that of z's), without the
// cancellation of r - x when x > 0 or r + x when x < 0.
vec2 gz_csqrt(vec2 z) {
  float r = length(z);
  if (r == 0.0) return vec2(0.0);
  if (z.x >= 0.0) {
    float re = sqrt(0.5 * (r + z.x));
    return vec2(re, 0.5 * z.y / re);
  }
  float im = sqrt(0.5 * (r - z.x));
  return vec2(0.5 * abs(z.y) / im, z.y < 0.0 ? -im : im);
}
)"},
      {"gz_fresnel_complex",
       {"gz_complex"},
       R"(// Unpolarized Fresnel reflectance from air into eta + ik (models/classic_models.h, fresnel_complex).
float gz_fresnel_complex(float cos_theta, float eta, float k) {
  float c = clamp(cos_theta, 0.0, 1.0);
  vec2 e = vec2(eta, k);
  vec2 sin2_t = gz_cdiv(vec2((1.0 - c) * (1.0 + c), 0.0), gz_cmul(e, e));
  vec2 cos_t = gz_csqrt(vec2(1.0, 0.0) - sin2_t);
  vec2 e_cos_t = gz_cmul(e, cos_t);
  vec2 den_s = vec2(c, 0.0) + e_cos_t, den_p = c * e + cos_t;
  if (dot(den_s, den_s) == 0.0 || dot(den_p, den_p) == 0.0) return 1.0;
  vec2 r_s = gz_cdiv(vec2(c, 0.0) - e_cos_t, den_s);
  vec2 r_p = gz_cdiv(c * e - cos_t, den_p);
  return clamp(0.5 * (dot(r_s, r_s) + dot(r_p, r_p)), 0.0, 1.0);
}
)"},
  };
  return list;
}

const Helper& helper(const std::string& name) {
  for (const Helper& h : helpers())
    if (name == h.name) return h;
  throw std::logic_error("no GLSL helper named '" + name + "' (models/glsl.cpp)");
}

void collect(const std::string& name, std::set<std::string>& out) {
  if (!out.insert(name).second) return;
  for (const char* need : helper(name).needs) collect(need, out);
}

}  // namespace

std::vector<std::string> glsl_helper_names() {
  std::vector<std::string> names;
  for (const Helper& h : helpers()) names.push_back(h.name);
  return names;
}

std::string glsl_helpers(const std::vector<std::string>& names) {
  std::set<std::string> wanted;
  for (const std::string& name : names) collect(name, wanted);
  std::string out;
  for (const Helper& h : helpers()) {
    if (!wanted.count(h.name)) continue;
    std::string guard = std::string("GZ_HELPER_") + h.name;
    out += "#ifndef " + guard + "\n#define " + guard + " 1\n" + h.code + "#endif\n";
  }
  return out;
}

}  // namespace ganzfeld
