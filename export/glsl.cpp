#include "export/glsl.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "export/glsl_f.h"
#include "scene/plan.h"
#include "tables/cache.h"
#include "tables/sample.h"
#include "util/error.h"
#include "util/literal.h"

namespace ganzfeld::exporting {

using namespace ganzfeld::tables;

namespace {

/// A GLSL float literal that reads back as the float nearest to x.
std::string literal(double x) { return decimal_literal(x); }

/// A comment line-safe copy of text (no newlines; no "*/" since we use // comments anyway).
std::string comment_text(const std::string& text) {
  std::string out;
  for (char c : text) out += (c == '\n' || c == '\r') ? ' ' : c;
  return out;
}

/// The GLSL index coordinate u of x on `axis` (Axis::index_coordinate). The sinh mappings also take
/// the width w and V (docs/lut-format.md), V computed here in double as the CPU does.
std::string index_call(const Axis& axis, const std::string& x) {
  std::string call = "gz_index_" + std::string(to_string(axis.mapping)) + "(" + x + ", " + literal(axis.min) + ", " +
                     literal(axis.max);
  if (axis.has_width()) {
    const double range = axis.mapping == Mapping::sinh ? 0.5 * (axis.max - axis.min) : axis.max - axis.min;
    call += ", " + literal(axis.width) + ", " + literal(std::asinh(range / axis.width));
  }
  return call + ")";
}

/// "true"/"false" per axis: Catmull–Rom reflects at the ends of an even axis (tables::is_even_axis).
std::string even_flags(const Table& table) {
  std::string out;
  for (const Axis& axis : table.axes)
    out += std::string(out.empty() ? "" : ", ") + (is_even_axis(axis) ? "true" : "false");
  return table.axes.size() == 1 ? out : "bvec3(" + out + ")";
}

/// The lookup call of `table` at index coordinates `u` (tables::sample_axes: linear, Catmull–Rom or
/// the b-spline).
std::string lookup_call(const Table& table, const std::string& u) {
  std::string count;
  for (const Axis& axis : table.axes) count += (count.empty() ? "" : ", ") + std::to_string(axis.count);
  if (table.axes.size() == 3) count = "ivec3(" + count + ")";
  const std::string dims = table.axes.size() == 3 ? "3" : "1";
  // A hardware-filtered table's bound covers the GPU's filter (check_table: linear and b-spline):
  // texture() whatever GANZFELD_HARDWARE_FILTER says.
  const bool filtered = table.filter == Filter::hardware;
  const std::string kind = table.interpolation == Interpolation::catmull_rom ? "_catmull_rom"
                           : table.interpolation == Interpolation::bspline
                               ? (filtered ? "_bspline_filtered" : "_bspline")
                           : filtered ? "_filtered"
                                      : "";
  const bool even = table.interpolation == Interpolation::catmull_rom;  // only Catmull–Rom folds the ends
  const std::string call =
      "gz_lookup" + dims + kind + "(table, " + u + ", " + count + (even ? ", " + even_flags(table) : "") + ")";
  if (table.encoding != Encoding::unorm16) return call;
  // unorm16: the texture holds u / 65535 (R16 normalized); both lookups are affine (weights sum
  // to 1), so offset + scale x lookup(codes) = lookup(offset + scale x codes), tables::sample's value.
  return literal(table.unorm.offset) + " + " + literal(table.unorm.scale) + " * " + call;
}

}  // namespace

std::string glsl_identifier(const std::string& text) {
  std::string out = "gz_";
  bool pending = false;
  for (unsigned char c : text) {
    if (std::isalnum(c)) {
      if (pending && out.back() != '_') out += '_';
      pending = false;
      out += static_cast<char>(c);
    } else {
      pending = true;
    }
  }
  if (pending && out.back() != '_') out += '_';
  if (out.back() == '_' && out.size() > 3) out.pop_back();
  return out;
}

std::string glsl_function_name(const std::string& spec, Law law) {
  return glsl_identifier(spec + "_" + to_string(law));
}

std::string glsl_sampler_name(const std::string& spec, Law law) {
  return "gz_tex" + glsl_identifier(spec + "_" + to_string(law)).substr(2);
}

const char* glsl_sampler_type(Law law) { return law == Law::g ? "sampler3D" : "sampler2D"; }

std::string glsl_common() {
  // The formulas are those of tables/table.cpp (Axis::index_coordinate) and tables/sample.cpp; the cos
  // mapping u = acos(1 - 2t)/pi is evaluated as (2/pi) asin(sqrt(t)), and from the far end for
  // t > 1/2, because acos(1 - 2t) loses all of t below 1e-8 in float. GLSL's own asin/atan are
  // not used (their accuracy is implementation-defined): see gz_asin_sqrt.
  return R"(#ifndef GANZFELD_COMMON_GLSL
#define GANZFELD_COMMON_GLSL 1
// ganzfeld shared helpers: the axis mappings, the lobe frame and the linear and Catmull-Rom
// lookups of tables/sample.h.
// GLSL 4.30 core and GLSL ES 3.00. Textures must be complete without mipmaps (set
// GL_TEXTURE_MIN_FILTER to GL_NEAREST or GL_LINEAR, or GL_TEXTURE_MAX_LEVEL to 0), or texelFetch
// returns 0.
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler3D;

// Inverse trigonometry to float precision. GLSL leaves the accuracy of asin and atan to the
// implementation, and real ones are coarse (Mesa's polynomial asin is off by ~1e-4), which moved
// lookups by up to 2e-3 relative; these are Cephes' single-precision kernels (S. Moshier,
// asinf.c and atanf.c: relative error ~2e-7 on their reduced ranges) using only +, *, / and sqrt.
// asin(sqrt(t)) for t in [0, 1/2]:
float gz_asin_sqrt(float t) {
  bool reduce = t > 0.25;               // asin(a) = pi/2 - 2 asin(sqrt((1 - a)/2)) for a > 1/2
  float a = sqrt(t);
  float z = reduce ? 0.5 * (1.0 - a) : t;
  float x = reduce ? sqrt(z) : a;
  float p = ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z + 7.4953002686e-2) * z
             + 1.6666752422e-1) * z * x + x;
  return reduce ? 1.5707963268 - 2.0 * p : p;
}
// atan(r) for r in [0, 1].
float gz_atan01(float r) {
  bool reduce = r > 0.4142135624;       // atan(r) = pi/4 + atan((r - 1)/(r + 1))
  float x = reduce ? (r - 1.0) / (r + 1.0) : r;
  float z = x * x;
  float p = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * x + x;
  return reduce ? 0.7853981634 + p : p;
}
// |atan2(s, c)| in [0, pi] (not both zero).
float gz_abs_angle(float s, float c) {
  float a = abs(s), b = abs(c);
  float angle = a <= b ? gz_atan01(a / b) : 1.5707963268 - gz_atan01(b / a);
  return c < 0.0 ? 3.1415926536 - angle : angle;
}

// Normalized coordinate t in [0, 1] of x on the axis [lo, hi], clamped at the ends.
float gz_unit(float x, float lo, float hi) { return clamp((x - lo) / (hi - lo), 0.0, 1.0); }
// Index coordinate u in [0, 1] (node k at u = k / (count - 1)) for each mapping (docs/lut-format.md).
float gz_index_linear(float x, float lo, float hi) { return gz_unit(x, lo, hi); }
float gz_index_sqrt(float x, float lo, float hi) { return sqrt(gz_unit(x, lo, hi)); }
float gz_index_cos(float x, float lo, float hi) {
  float t = gz_unit(x, lo, hi);
  if (t <= 0.5) return 0.636619772 * gz_asin_sqrt(t);
  return 1.0 - 0.636619772 * gz_asin_sqrt(gz_unit(hi - x, 0.0, hi - lo));
}

// asinh(x), Cephes' single-precision kernel (asinhf.c: relative error ~9e-8 for |x| < 1/2, where
// log(x + sqrt(x^2 + 1)) would lose x to cancellation); log above (|x| <= 1e18, far beyond any
// axis: (x - c)/w <= pi/w).
float gz_asinh(float x) {
  float a = abs(x), z = a * a;
  float p = a < 0.5 ? (((2.0122003309e-2 * z - 4.2699340972e-2) * z + 7.4847586088e-2) * z - 1.6666288134e-1) * z * a + a
                    : log(a + sqrt(z + 1.0));
  return x < 0.0 ? -p : p;
}
// The sinh mappings (version 2): w the axis' width, V = asinh(half range / w) (sinh) or
// asinh(range / w) (sinh_max), both as stored/computed by tables/table.cpp.
float gz_index_sinh(float x, float lo, float hi, float w, float V) {
  float c = 0.5 * (lo + hi);
  return clamp(0.5 * (gz_asinh((clamp(x, lo, hi) - c) / w) / V + 1.0), 0.0, 1.0);
}
float gz_index_sinh_max(float x, float lo, float hi, float w, float V) {
  return clamp(1.0 - gz_asinh((hi - clamp(x, lo, hi)) / w) / V, 0.0, 1.0);
}

// cos of the angle between v and the unit normal n (1 for v = 0), as tables::coordinates.
float gz_cos_theta(vec3 v, vec3 n) {
  float len = length(v);
  return len > 0.0 ? clamp(dot(v, n) / len, -1.0, 1.0) : 1.0;
}
// Angle between the tangential parts of i and j, in [0, pi]; 0 when either lies along n.
float gz_relative_azimuth(vec3 i, vec3 j, vec3 n) {
  vec3 it = i - dot(i, n) * n;
  vec3 jt = j - dot(j, n) * n;
  if (length(it) <= 0.0 || length(jt) <= 0.0) return 0.0;
  return gz_abs_angle(dot(cross(it, jt), n), dot(it, jt));
}
// sin of the angle between v and the unit normal n (0 for v = 0), from the cross product: exact to
// float precision near the normal, where sqrt(1 - cos^2) would keep only half the digits.
float gz_sin_theta(vec3 v, vec3 n) {
  float len = length(v);
  return len > 0.0 ? min(length(cross(v, n)) / len, 1.0) : 0.0;
}
// The lobe frame of version-2 g tables (tables/frame.h, lobe_coordinates): (theta_j, psi, beta)
// of the sky's pole i and the viewing direction j about the lobe's peak p(j); s = -1 when p is
// the mirror direction of j, +1 when it is j (retro). j below the horizon counts as on it, as on
// the CPU (j.n clamped to 0). cos and sin of the relative azimuth phi come from the tangential
// parts (phi = 0 when either is 0), the angles from gz_abs_angle. gz_lobe_frame also returns the
// unit pole's components (i.p, i.e1, i.e2) and (cos, sin) of theta_j, which the warped frame uses.
void gz_lobe_frame(vec3 i, vec3 j, vec3 n, float s, out vec3 angles, out vec3 components, out vec2 cs_j) {
  float ci = gz_cos_theta(i, n), si = gz_sin_theta(i, n);
  float cj = gz_cos_theta(j, n), sj = gz_sin_theta(j, n);
  if (cj <= 0.0) { cj = 0.0; sj = 1.0; }
  vec3 it = i - dot(i, n) * n, jt = j - dot(j, n) * n;
  vec2 cs = vec2(dot(it, jt), abs(dot(cross(it, jt), n)));
  float r = length(cs);
  cs = r > 0.0 ? cs / r : vec2(1.0, 0.0);
  float ip = s * si * sj * cs.x + ci * cj;
  float ie1 = -s * si * cj * cs.x + ci * sj;
  float ie2 = si * cs.y;
  float beta = (ie1 == 0.0 && ie2 == 0.0) ? 0.0 : gz_abs_angle(ie2, ie1);
  angles = vec3(gz_abs_angle(sj, cj), gz_abs_angle(length(vec2(ie1, ie2)), ip), beta);
  components = vec3(ip, ie1, ie2);
  cs_j = vec2(cj, sj);
}
vec3 gz_lobe_coordinates(vec3 i, vec3 j, vec3 n, float s) {
  vec3 angles, components;
  vec2 cs_j;
  gz_lobe_frame(i, j, n, s, angles, components, cs_j);
  return angles;
}
// The warped frame (version 4, tables/frame.h, warped_offset): the offset of the sky's boundary
// from the lobe, with the warp (shift, along, across) at theta_j and the table's mix:
// q = i.p + shift i.e1, r^2 = along^2 (i.e1)^2 + across^2 (i.e2)^2,
// offset = mix (1 + q / sqrt(q^2 + r^2)) / 2 + (1 - mix) (1 - psi / pi).
float gz_warped_offset(vec3 warp, float mixing, vec3 c, float psi) {
  float q = c.x + warp.x * c.y;
  float d = sqrt(q * q + warp.y * warp.y * c.y * c.y + warp.z * warp.z * c.z * c.z);
  float lobe = d > 0.0 ? 0.5 * (1.0 + q / d) : 0.5;
  return mixing * lobe + (1.0 - mixing) * (1.0 - psi / 3.1415926536);
}
// The third axis (tables/frame.h, warped_beta): beta blended with the edge's direction where the
// lobe is round, atan2(across i.e2, along i.e1), by the table's beta_whitening.
float gz_warped_beta(vec3 warp, float whitening, vec3 c, float beta) {
  float whitened = (c.y == 0.0 && c.z == 0.0) ? beta : gz_abs_angle(warp.z * c.z, warp.y * c.y);
  return (1.0 - whitening) * beta + whitening * whitened;
}
// The envelope A(theta_j) = (cos + sqrt(cos^2 + width^2 sin^2)) / 2 the stored g / A is multiplied by.
float gz_warp_envelope(vec2 cs_j, float width) {
  return 0.5 * (cs_j.x + sqrt(cs_j.x * cs_j.x + width * width * cs_j.y * cs_j.y));
}

// j moved onto the horizon when it is below it (interpolated normals at silhouettes), as the
// rasterizer does for the sky and the Ganzfeld (rasterizer/shading.h).
vec3 gz_clamp_to_horizon(vec3 j, vec3 n) {
  float c = dot(j, n);
  if (c >= 0.0) return j;
  vec3 t = j - c * n;
  float r = length(t);
  if (r > 0.0) return t / r;
  vec3 a = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  return normalize(a - dot(a, n) * n);
}

// The cell of index coordinate u on an axis of `count` nodes: lower node k and fraction t.
void gz_cell(float u, int count, out int k, out float t) {
  float s = u * float(count - 1);
  k = min(int(floor(s)), count - 2);
  t = s - float(k);
}
// Linear interpolation by the GPU's filter: one texture() at the texel centre rule (needs
// GL_LINEAR filtering and GL_CLAMP_TO_EDGE; the weights may be rounded to 8 bits).
float gz_lookup1_filtered(highp sampler2D table, float u, int count) {
  return texture(table, vec2((u * float(count - 1) + 0.5) / float(count), 0.5)).r;
}
float gz_lookup3_filtered(highp sampler3D table, vec3 u, ivec3 count) {
  vec3 s = (u * vec3(count - 1) + 0.5) / vec3(count);
  return texture(table, s.zyx).r;
}
// Linear interpolation of a 1-D table stored as a count x 1 texture.
float gz_lookup1(highp sampler2D table, float u, int count) {
#ifdef GANZFELD_HARDWARE_FILTER
  return gz_lookup1_filtered(table, u, count);
#else
  int k; float t;
  gz_cell(u, count, k, t);
  return mix(texelFetch(table, ivec2(k, 0), 0).r, texelFetch(table, ivec2(k + 1, 0), 0).r, t);
#endif
}
// Trilinear interpolation of a 3-D table; u and count are slowest axis first (texture z, y, x).
float gz_lookup3(highp sampler3D table, vec3 u, ivec3 count) {
#ifdef GANZFELD_HARDWARE_FILTER
  return gz_lookup3_filtered(table, u, count);
#else
  int k0, k1, k2;
  float t0, t1, t2;
  gz_cell(u.x, count.x, k0, t0);
  gz_cell(u.y, count.y, k1, t1);
  gz_cell(u.z, count.z, k2, t2);
  float c00 = mix(texelFetch(table, ivec3(k2, k1, k0), 0).r, texelFetch(table, ivec3(k2 + 1, k1, k0), 0).r, t2);
  float c01 = mix(texelFetch(table, ivec3(k2, k1 + 1, k0), 0).r, texelFetch(table, ivec3(k2 + 1, k1 + 1, k0), 0).r, t2);
  float c10 = mix(texelFetch(table, ivec3(k2, k1, k0 + 1), 0).r, texelFetch(table, ivec3(k2 + 1, k1, k0 + 1), 0).r, t2);
  float c11 = mix(texelFetch(table, ivec3(k2, k1 + 1, k0 + 1), 0).r,
                  texelFetch(table, ivec3(k2 + 1, k1 + 1, k0 + 1), 0).r, t2);
  return mix(mix(c00, c01, t1), mix(c10, c11, t1), t0);
#endif
}

// Catmull–Rom (version 2, tables::axis_taps): the weights of nodes k-1 .. k+2 around index
// coordinate u on an axis of count >= 4 nodes. A node beyond an end is folded into the real ones:
// reflected on an even axis (an azimuth: p[-1] = p[1]), else extrapolated quadratically
// (p[-1] = 3 p[0] - 3 p[1] + p[2]); its weight is then 0 and its (clamped) fetch harmless.
void gz_catmull_rom(float u, int count, bool even, out int k, out vec4 w) {
  float t;
  gz_cell(u, count, k, t);
  float t2 = t * t, t3 = t2 * t;
  w = 0.5 * vec4(-t3 + 2.0 * t2 - t, 3.0 * t3 - 5.0 * t2 + 2.0, -3.0 * t3 + 4.0 * t2 + t, t3 - t2);
  if (k == 0) {
    if (even) w.z += w.x; else w += vec4(0.0, 3.0, -3.0, 1.0) * w.x;
    w.x = 0.0;
  }
  if (k == count - 2) {
    if (even) w.y += w.w; else w += vec4(1.0, -3.0, 3.0, 0.0) * w.w;
    w.w = 0.0;
  }
}
// For hardware filtering: the 4 taps as 3 texture coordinates and weights. The middle weights are
// >= 0 for every t, also with an end folded in, so nodes k and k+1 are one linear fetch at
// k + w2/(w1 + w2) (w1 + w2 >= 1): 3 fetches per axis instead of 4, 27 instead of 64 in 3-D.
void gz_catmull_rom_linear(float u, int count, bool even, out vec3 x, out vec3 w) {
  int k;
  vec4 c;
  gz_catmull_rom(u, count, even, k, c);
  w = vec3(c.x, c.y + c.z, c.w);
  x = (vec3(float(max(k - 1, 0)), float(k) + c.z / w.y, float(min(k + 2, count - 1))) + 0.5) / float(count);
}
// Catmull–Rom lookup of a 1-D table stored as a count x 1 texture.
float gz_lookup1_catmull_rom(highp sampler2D table, float u, int count, bool even) {
#ifdef GANZFELD_HARDWARE_FILTER
  vec3 x, w;
  gz_catmull_rom_linear(u, count, even, x, w);
  return w.x * texture(table, vec2(x.x, 0.5)).r + w.y * texture(table, vec2(x.y, 0.5)).r +
         w.z * texture(table, vec2(x.z, 0.5)).r;
#else
  int k;
  vec4 w;
  gz_catmull_rom(u, count, even, k, w);
  vec4 p = vec4(texelFetch(table, ivec2(max(k - 1, 0), 0), 0).r, texelFetch(table, ivec2(k, 0), 0).r,
                texelFetch(table, ivec2(k + 1, 0), 0).r, texelFetch(table, ivec2(min(k + 2, count - 1), 0), 0).r);
  return dot(w, p);
#endif
}
// Catmull–Rom lookup of a 3-D table (tensor product); u, count and even slowest axis first.
float gz_lookup3_catmull_rom(highp sampler3D table, vec3 u, ivec3 count, bvec3 even) {
  float sum = 0.0;
#ifdef GANZFELD_HARDWARE_FILTER
  vec3 x0, x1, x2, w0, w1, w2;
  gz_catmull_rom_linear(u.x, count.x, even.x, x0, w0);
  gz_catmull_rom_linear(u.y, count.y, even.y, x1, w1);
  gz_catmull_rom_linear(u.z, count.z, even.z, x2, w2);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      vec3 row = vec3(texture(table, vec3(x2.x, x1[b], x0[a])).r, texture(table, vec3(x2.y, x1[b], x0[a])).r,
                      texture(table, vec3(x2.z, x1[b], x0[a])).r);
      sum += w0[a] * w1[b] * dot(w2, row);
    }
#else
  int k0, k1, k2;
  vec4 w0, w1, w2;
  gz_catmull_rom(u.x, count.x, even.x, k0, w0);
  gz_catmull_rom(u.y, count.y, even.y, k1, w1);
  gz_catmull_rom(u.z, count.z, even.z, k2, w2);
  ivec4 n2 = clamp(ivec4(k2 - 1, k2, k2 + 1, k2 + 2), 0, count.z - 1);
  for (int a = 0; a < 4; ++a) {
    int n0 = clamp(k0 - 1 + a, 0, count.x - 1);
    float plane = 0.0;
    for (int b = 0; b < 4; ++b) {
      int n1 = clamp(k1 - 1 + b, 0, count.y - 1);
      vec4 row = vec4(texelFetch(table, ivec3(n2.x, n1, n0), 0).r, texelFetch(table, ivec3(n2.y, n1, n0), 0).r,
                      texelFetch(table, ivec3(n2.z, n1, n0), 0).r, texelFetch(table, ivec3(n2.w, n1, n0), 0).r);
      plane += w1[b] * dot(w2, row);
    }
    sum += w0[a] * plane;
  }
#endif
  return sum;
}

// The cubic b-spline (version 6, tables::bspline_taps; tables/bspline.h): the table holds the
// spline's coefficients, one beyond each end of every axis, s = 1 + u (count - 3). Around s the four
// weights are >= 0 and read as two pairs of neighbouring coefficients: (k - 1, k) with weight g.x,
// the second at fraction f.x, and (k + 1, k + 2) with g.y and f.y.
void gz_bspline(float u, int count, out int k, out vec2 g, out vec2 f) {
  float s = 1.0 + clamp(u, 0.0, 1.0) * float(count - 3);
  k = min(int(floor(s)), count - 3);
  float t = s - float(k), r = 1.0 - t, t2 = t * t, t3 = t2 * t;
  vec4 b = vec4(r * r * r, 3.0 * t3 - 6.0 * t2 + 4.0, -3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0, t3) / 6.0;
  g = vec2(b.x + b.y, b.z + b.w);
  f = vec2(b.y / g.x, b.w / g.y);
}
// For hardware filtering: the two pairs' texture coordinates (texel centre rule) and weights.
void gz_bspline_linear(float u, int count, out vec2 x, out vec2 g) {
  int k;
  vec2 f;
  gz_bspline(u, count, k, g, f);
  x = (vec2(float(k - 1), float(k + 1)) + f + 0.5) / float(count);
}
// For texelFetch: the four coefficients' weights (coefficients k - 1 .. k + 2).
void gz_bspline_taps(float u, int count, out int k, out vec4 w) {
  vec2 g, f;
  gz_bspline(u, count, k, g, f);
  w = vec4(g.x * (1.0 - f.x), g.x * f.x, g.y * (1.0 - f.y), g.y * f.y);
}
// B-spline lookups by the GPU's filter: 2 fetches per axis (2 in 1-D, 8 in 3-D).
float gz_lookup1_bspline_filtered(highp sampler2D table, float u, int count) {
  vec2 x, g;
  gz_bspline_linear(u, count, x, g);
  return g.x * texture(table, vec2(x.x, 0.5)).r + g.y * texture(table, vec2(x.y, 0.5)).r;
}
float gz_lookup3_bspline_filtered(highp sampler3D table, vec3 u, ivec3 count) {
  vec2 x0, x1, x2, g0, g1, g2;
  gz_bspline_linear(u.x, count.x, x0, g0);
  gz_bspline_linear(u.y, count.y, x1, g1);
  gz_bspline_linear(u.z, count.z, x2, g2);
  float sum = 0.0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      sum += g0[a] * g1[b] * dot(g2, vec2(texture(table, vec3(x2.x, x1[b], x0[a])).r,
                                          texture(table, vec3(x2.y, x1[b], x0[a])).r));
  return sum;
}
// B-spline lookups with texelFetch (4 per axis), or the filtered ones under GANZFELD_HARDWARE_FILTER.
float gz_lookup1_bspline(highp sampler2D table, float u, int count) {
#ifdef GANZFELD_HARDWARE_FILTER
  return gz_lookup1_bspline_filtered(table, u, count);
#else
  int k;
  vec4 w;
  gz_bspline_taps(u, count, k, w);
  return dot(w, vec4(texelFetch(table, ivec2(k - 1, 0), 0).r, texelFetch(table, ivec2(k, 0), 0).r,
                     texelFetch(table, ivec2(k + 1, 0), 0).r, texelFetch(table, ivec2(k + 2, 0), 0).r));
#endif
}
float gz_lookup3_bspline(highp sampler3D table, vec3 u, ivec3 count) {
#ifdef GANZFELD_HARDWARE_FILTER
  return gz_lookup3_bspline_filtered(table, u, count);
#else
  int k0, k1, k2;
  vec4 w0, w1, w2;
  gz_bspline_taps(u.x, count.x, k0, w0);
  gz_bspline_taps(u.y, count.y, k1, w1);
  gz_bspline_taps(u.z, count.z, k2, w2);
  float sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    float plane = 0.0;
    for (int b = 0; b < 4; ++b) {
      ivec2 yz = ivec2(k1 - 1 + b, k0 - 1 + a);
      vec4 row = vec4(texelFetch(table, ivec3(k2 - 1, yz), 0).r, texelFetch(table, ivec3(k2, yz), 0).r,
                      texelFetch(table, ivec3(k2 + 1, yz), 0).r, texelFetch(table, ivec3(k2 + 2, yz), 0).r);
      plane += w1[b] * dot(w2, row);
    }
    sum += w0[a] * plane;
  }
  return sum;
#endif
}
#endif  // GANZFELD_COMMON_GLSL
)";
}

namespace {

/// Which lookup the function performs and the bound covers, and its texture fetches.
std::string lookup_description(const Table& table) {
  const int n = fetches(table);
  const std::string count = std::to_string(n) + " texture fetch" + (n == 1 ? "" : "es");
  if (table.filter == Filter::hardware)
    return count +
           ", hardware filtering (GL_LINEAR, GL_CLAMP_TO_EDGE); the bound covers filter weights of 8 "
           "bits, rounded or truncated";
  return count +
         " (texelFetch, weights in full precision; the bound is for this lookup, not for "
         "GANZFELD_HARDWARE_FILTER)";
}

/// The comment block above a table's function: metadata, the table's error, axes and texture.
std::string table_comment(const Table& table) {
  std::ostringstream s;
  s << "// ---------------------------------------------------------------------------------------------\n"
    << "// ganzfeld table: law " << to_string(table.law) << " of " << comment_text(table.model) << "\n"
    << "// made by: " << comment_text(table.command) << "\n"
    << "// ganzfeld " << comment_text(table.version) << ", format version " << table.format_version << ", encoding "
    << to_string(table.encoding) << ", frame " << to_string(table.frame);
  if (table.frame != Frame::cosines) s << " (peak " << to_string(table.peak) << ")";
  s << ", " << to_string(table.interpolation) << " lookup, cubature tolerance " << literal(table.tolerance) << "\n"
    << "// lookup: " << lookup_description(table) << "\n"
    << "// error: lookup <= " << literal(table.lookup_error);
  if (table.interpolation_checks > 0)
    s << " (validated at " << table.interpolation_checks << " points: largest measured "
      << literal(table.interpolation_error) << ")";
  if (table.min_cos_j > 0.0) s << " for j.n >= " << literal(table.min_cos_j) << " (not a bound below)";
  s << "; node_error <= " << literal(table.node_error) << "\n// axes, slowest first:\n";
  for (const Axis& axis : table.axes) {
    s << "//   " << axis.name << " in [" << literal(axis.min) << ", " << literal(axis.max) << "], " << axis.count
      << " nodes, " << to_string(axis.mapping) << " mapping";
    if (axis.has_width()) s << " (width " << literal(axis.width) << ")";
    s << "\n";
  }
  s << "// texture: " << glsl_sampler_type(table.law) << ", one channel ("
    << (table.encoding == Encoding::unorm16 ? "R16, normalized unsigned 16-bit codes" : "R32F or R16F") << "), ";
  if (table.law == Law::g)
    s << "width " << table.axes[2].count << " (" << table.axes[2].name << "), height " << table.axes[1].count << " ("
      << table.axes[1].name << "), depth " << table.axes[0].count << " (" << table.axes[0].name << ")\n";
  else s << "width " << table.axes[0].count << ", height 1\n";
  return s.str();
}

/// The warp samples of a warped table as a GLSL constant array named `name`.
std::string warp_array(const Table& table, const std::string& name) {
  std::ostringstream s;
  const std::size_t K = table.warp.samples.size();
  s << "// the warp (shift, along, across) at theta_j's index coordinate k / " << K - 1 << " (tables/frame.h)\n"
    << "const vec3 " << name << "[" << K << "] = vec3[" << K << "](";
  for (std::size_t k = 0; k < K; ++k) {
    const WarpSample& w = table.warp.samples[k];
    s << (k ? ",\n    " : "\n    ") << "vec3(" << literal(w.shift) << ", " << literal(w.along) << ", "
      << literal(w.across) << ")";
  }
  s << ");\n";
  return s.str();
}

/// The body of a warped g function: the lobe frame's angles and components, the warp at theta_j,
/// the index coordinates, the lookup times the envelope.
std::string warped_body(const Table& table, const std::string& warp_name) {
  std::ostringstream s;
  const int last = static_cast<int>(table.warp.samples.size()) - 1;
  s << "  vec3 angles, c;\n  vec2 cs_j;\n"
    << "  gz_lobe_frame(i, j, n, " << (table.peak == PeakKind::retro ? "1.0" : "-1.0") << ", angles, c, cs_j);\n"
    << "  float v = " << index_call(table.axes[0], "angles.x") << ";\n"
    << "  float t = v * " << literal(last) << ";\n"
    << "  int k = min(int(floor(t)), " << last - 1 << ");\n"
    << "  vec3 warp = mix(" << warp_name << "[k], " << warp_name << "[k + 1], t - float(k));\n"
    << "  vec3 u = vec3(v, gz_warped_offset(warp, " << literal(table.warp.mix) << ", c, angles.y),\n"
    << "                "
    << index_call(table.axes[2], table.warp.beta_whitening != 0.0
                                     ? "gz_warped_beta(warp, " + literal(table.warp.beta_whitening) + ", c, angles.z)"
                                     : std::string("angles.z"))
    << ");\n"
    << "  return "
    << (table.warp.envelope > 0.0 ? "gz_warp_envelope(cs_j, " + literal(table.warp.envelope) + ") * " : "") << "("
    << lookup_call(table, "u") << ");\n";
  return s.str();
}

/// The body of a g function: the axis coordinates (cosines or lobe frame), their index
/// coordinates, the lookup.
std::string g_body(const Table& table) {
  std::ostringstream s;
  std::string x[3] = {"gz_cos_theta(i, n)", "gz_cos_theta(j, n)", "gz_relative_azimuth(i, j, n)"};
  if (table.frame == Frame::lobe) {
    s << "  vec3 y = gz_lobe_coordinates(i, j, n, " << (table.peak == PeakKind::retro ? "1.0" : "-1.0") << ");\n";
    x[0] = "y.x", x[1] = "y.y", x[2] = "y.z";
  }
  s << "  vec3 u = vec3(" << index_call(table.axes[0], x[0]) << ",\n"
    << "                " << index_call(table.axes[1], x[1]) << ",\n"
    << "                " << index_call(table.axes[2], x[2]) << ");\n"
    << "  return " << lookup_call(table, "u") << ";\n";
  return s.str();
}

}  // namespace

std::string glsl_table_function(const Table& table) {
  check_table(table);
  const std::string name = glsl_function_name(table.model, table.law);
  std::ostringstream s;
  s << table_comment(table);
  if (table.law == Law::g && table.frame == Frame::warped) {
    s << warp_array(table, name + "_warp")
      << "// i: the sky's pole, j: towards the viewer, n: unit normal (any common frame)\n"
      << "float " << name << "(highp sampler3D table, vec3 i, vec3 j, vec3 n) {\n"
      << warped_body(table, name + "_warp") << "}\n";
  } else if (table.law == Law::g) {
    s << "// i: the sky's pole, j: towards the viewer, n: unit normal (any common frame)\n"
      << "float " << name << "(highp sampler3D table, vec3 i, vec3 j, vec3 n) {\n"
      << g_body(table) << "}\n";
  } else {
    const bool h = table.law == Law::h;
    s << "float " << name << "(highp sampler2D table, vec3 " << (h ? "j" : "i") << ", vec3 n) {\n"
      << "  return " << lookup_call(table, index_call(table.axes[0], h ? "gz_cos_theta(j, n)" : "gz_cos_theta(i, n)"))
      << ";\n}\n";
  }
  return s.str();
}

std::string lookup_scheme(const Table& table) {
  std::ostringstream out;
  out << to_string(table.frame) << " frame";
  if (table.frame != Frame::cosines) out << " (" << to_string(table.peak) << " peak)";
  out << ", " << to_string(table.interpolation) << ", ";
  for (std::size_t d = 0; d < table.axes.size(); ++d) out << (d ? "x" : "") << table.axes[d].count;
  out << " nodes, " << to_string(table.encoding) << ", " << to_string(table.filter) << " (" << tables::fetches(table)
      << (tables::fetches(table) == 1 ? " fetch)" : " fetches)");
  return out.str();
}

std::string glsl_table_snippet(const Table& table) {
  const std::string function = glsl_table_function(table);  // checks the table first
  return glsl_common() + "\n" + function;
}

void check_table_is(const Table& table, const Model& model, Law law) {
  auto named = [](const std::string& spec, const std::string& content) {
    return "'" + spec + "'" + (content.empty() ? "" : " (data " + content + ")");
  };
  if (!tables::same_model(table, model) || table.law != law)
    throw InputError("table holds law " + std::string(to_string(table.law)) + " of " +
                     named(table.model, table.model_content) + " but the shader needs law " + to_string(law) + " of " +
                     named(model.spec(), model.content_digest()));
  check_table(table);
}

void check_scene_exportable(const Scene& scene) {
  bool collimated = false, extended = false;
  for (const Light& light : scene.lights) {
    collimated = collimated || light.type == Light::Type::collimated;
    extended = extended || light.type != Light::Type::collimated;
  }
  for (const SceneObject& object : scene.objects)
    for (const MaterialLobe& lobe : scene.materials.at(object.material).lobes) {
      if (collimated) glsl_model_f(*lobe.model);
      if (extended && has_mirror_delta(*lobe.model))
        throw InputError("model '" + lobe.spec +
                         "' has a mirror delta besides f (the coherent specular term rho_s) that "
                         "its tables do not hold; render adds it under skies and the Ganzfeld, the GLSL would not: "
                         "allowed: models without a mirror delta under extended lights");
      if (extended && !lobe.model->traits().isotropic)
        throw InputError("model '" + lobe.spec +
                         "' is anisotropic: its sky and Ganzfeld terms have no tables (a fourth "
                         "axis would be needed), so no GLSL; allowed: isotropic models under extended lights");
    }
}

namespace {

/// The GLSL expression of law g or h of a planned lobe: its closed form or its table function.
std::string law_expression(const scene::PlannedLobe& lobe, Law law) {
  const bool g = law == Law::g;
  if ((g ? lobe.g : lobe.h) == scene::LawOrigin::closed_form) return g ? "0.5 * (1.0 + dot(i, n))" : "1.0";
  return glsl_function_name(lobe.spec, law) + "(" + glsl_sampler_name(lobe.spec, law) +
         (g ? ", i, jc, n)" : ", jc, n)");
}

std::string vec3_literal(const Vec3& v) {
  return "vec3(" + literal(v[0]) + ", " + literal(v[1]) + ", " + literal(v[2]) + ")";
}
std::string vec3_literal(const Rgb& v) {
  return "vec3(" + literal(v[0]) + ", " + literal(v[1]) + ", " + literal(v[2]) + ")";
}

/// The GLSL a scene shader needs once per lobe and law: sampler uniforms, table functions, and f
/// of the lobes lit by a collimated light; each emitted once however many materials share it.
struct LobeCode {
  std::ostringstream uniforms, tables, fs;
  std::set<std::string> done;

  void add_table(const scene::PlannedLobe& lobe, Law law) {
    const scene::LawOrigin origin = law == Law::g ? lobe.g : lobe.h;
    if (origin == scene::LawOrigin::none || origin == scene::LawOrigin::closed_form) return;
    const tables::Table* table = (law == Law::g ? lobe.g_table : lobe.h_table).get();
    if (origin != scene::LawOrigin::table || table == nullptr)
      throw InputError("no table of law " + std::string(to_string(law)) + " of '" + lobe.spec +
                       "' for the scene shader");
    check_table_is(*table, *lobe.model, law);
    if (!done.insert(glsl_function_name(lobe.spec, law)).second) return;
    uniforms << "uniform highp " << glsl_sampler_type(law) << " " << glsl_sampler_name(lobe.spec, law) << ";\n";
    tables << glsl_table_function(*table);
  }
  void add_f(const scene::PlannedLobe& lobe) {
    if (done.insert(glsl_f_name(lobe.spec)).second) fs << glsl_model_f(*lobe.model);
  }
};

/// The lights as constants: GZ_LIGHTk_INTENSITY and, but for a Ganzfeld, GZ_LIGHTk_DIRECTION.
std::string light_constants(const std::vector<Light>& lights) {
  std::ostringstream out;
  for (std::size_t k = 0; k < lights.size(); ++k) {
    const Light& light = lights[k];
    out << "const vec3 GZ_LIGHT" << k << "_INTENSITY = " << vec3_literal(light.intensity) << ";";
    if (light.type != Light::Type::ganzfeld)
      out << "  const vec3 GZ_LIGHT" << k << "_DIRECTION = " << vec3_literal(glm::normalize(light.direction)) << ";";
    out << "  // "
        << (light.type == Light::Type::collimated      ? "collimated: irradiance H0, towards the source"
            : light.type == Light::Type::hemispherical ? "hemispherical sky: radiance N, its pole"
                                                       : "Ganzfeld: radiance N")
        << "\n";
  }
  return out.str();
}

/// Light k's contribution to a material: the sum over its lobes (weight x colour x law), in the
/// light field's own form (rasterizer/shading.h).
std::string light_term(const Light& light, std::size_t k, const scene::PlannedMaterial& lobes) {
  const std::string L = "GZ_LIGHT" + std::to_string(k);
  std::string sum;
  for (const scene::PlannedLobe& lobe : lobes) {
    const std::string law = light.type == Light::Type::collimated      ? glsl_f_name(lobe.spec) + "(i, j, n, t)"
                            : light.type == Light::Type::hemispherical ? law_expression(lobe, Law::g)
                                                                       : law_expression(lobe, Law::h);
    Rgb weighted{};
    for (int c = 0; c < 3; ++c) weighted[c] = lobe.weight * lobe.color[c];
    sum += (sum.empty() ? "" : "\n        + ") + vec3_literal(weighted) + " * " + law;
  }
  std::ostringstream out;
  switch (light.type) {
    case Light::Type::collimated:
      out << "  {  // light " << k << ": collimated, H0 (i.n) f(i, j); nothing in body shadow\n"
          << "    vec3 i = " << L << "_DIRECTION;\n"
          << "    float mi = dot(i, n);\n"
          << "    if (mi > 0.0 && dot(j, n) > 0.0)\n"
          << "      radiance += " << L << "_INTENSITY * mi * (" << sum << ");\n  }\n";
      break;
    case Light::Type::hemispherical:
      out << "  {  // light " << k << ": hemispherical sky, N g(i, j, n)\n"
          << "    vec3 i = " << L << "_DIRECTION;\n"
          << "    radiance += " << L << "_INTENSITY * (" << sum << ");\n  }\n";
      break;
    case Light::Type::ganzfeld:
      out << "  // light " << k << ": Ganzfeld, N h(j, n)\n"
          << "  radiance += " << L << "_INTENSITY * (" << sum << ");\n";
      break;
  }
  return out.str();
}

/// The function of material m: radiance towards j at normal n, summed over the lights.
std::string material_function(const std::string& name, std::size_t m, const std::string& material_name,
                              const std::vector<Light>& lights, const scene::PlannedMaterial& lobes) {
  std::ostringstream out;
  out << "// material " << m << " '" << comment_text(material_name) << "'\n"
      << "vec3 " << name << "(vec3 n, vec3 j, vec3 t) {\n"
      << "  vec3 jc = gz_clamp_to_horizon(j, n);\n"
      << "  vec3 radiance = vec3(0.0);\n";
  for (std::size_t k = 0; k < lights.size(); ++k) out << light_term(lights[k], k, lobes);
  out << "  return radiance;\n}\n\n";
  return out.str();
}

}  // namespace

std::string glsl_scene_shader(const Scene& scene, const scene::ShadingPlan& plan, const std::string& source) {
  LobeCode code;
  std::ostringstream materials, dispatch;
  for (std::size_t m = 0; m < plan.materials.size(); ++m) {
    if (!plan.material_used[m]) continue;
    for (const scene::PlannedLobe& lobe : plan.materials[m]) {
      if (plan.fields.collimated) code.add_f(lobe);
      code.add_table(lobe, Law::g);
      code.add_table(lobe, Law::h);
    }
    const std::string name = glsl_identifier("material_" + std::to_string(m) + "_" + scene.materials[m].name);
    materials << material_function(name, m, scene.materials[m].name, scene.lights, plan.materials[m]);
    dispatch << "  if (material == " << m << ") return " << name << "(n, j, t);\n";
  }
  std::ostringstream out;
  out << "// ganzfeld scene shader for " << comment_text(source) << " (generated; docs/shaders.md).\n"
      << "// Radiance towards the viewer, as the software rasterizer computes it (rasterizer/shading.h):\n"
      << "//   collimated  H0 (i.n) f(i, j)   hemispherical sky  N g(i, j, n)   Ganzfeld  N h(j, n)\n"
      << "// summed over lights and lobes (weight x colour). Bind every gz_tex_* sampler below to its table.\n"
      << "// Include after #version (430 core or 300 es).\n\n"
      << glsl_common() << "\n"
      << code.uniforms.str() << "\n"
      << code.tables.str() << "\n"
      << glsl_helpers({"gz_frame"}) << code.fs.str() << "\n"
      << "// Lights (world space; directions unit, towards the source), from the scene file.\n"
      << light_constants(scene.lights) << "\n"
      << materials.str()
      << "// Radiance of material `material` (its index in the scene file) at unit normal n, towards unit j;\n"
      << "// t the surface's tangent (anisotropic lobes are oriented by it: the object's \"tangent\" rule of the\n"
      << "// scene file, gz_brush_tangent; isotropic ones ignore it).\n"
      << "vec3 gz_scene_radiance(int material, vec3 n, vec3 j, vec3 t) {\n"
      << dispatch.str() << "  return vec3(0.0);\n}\n"
      << "vec3 gz_scene_radiance(int material, vec3 n, vec3 j) {\n"
      << "  return gz_scene_radiance(material, n, j, gz_brush_tangent(n, vec3(0.0, 1.0, 0.0), true));\n}\n";
  return out.str();
}

}  // namespace ganzfeld::exporting
