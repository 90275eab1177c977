// A baked table of one law (g, h or a) of one model: axes, values, per-entry error, metadata.
// The file format, the axis mappings and the memory layout are specified in docs/lut-format.md;
// the formulas below are the normative ones and the document quotes them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "integrate/laws.h"
#include "util/angles.h"

namespace ganzfeld::tables {

/// Throws InputError unless `law` has tables (g, h, a): "law 'f' has no table; allowed: g, h, a".
void require_tabulated(Law law);
/// parse_law for a flag that names a tabulated law; refusals name `flag` and the text.
Law parse_tabulated_law(const std::string& flag, const std::string& text);

/// The version of docs/lut-format.md this code writes: 6 (the b-spline interpolation; version 3 is
/// the parameter tables of tables/param_table.h). Versions 1 (cosine axes, linear lookup, no frame
/// or interpolation attributes), 2 (no warped frame, no filter attribute), 4 (the warped frame and
/// the lookup filter, beta unwhitened) and 5 (beta may be whitened) are still read.
inline constexpr int kFormatVersion = 6;
inline constexpr int kOldestFormatVersion = 1;
/// The first version with the warped frame and the lookup filter attributes.
inline constexpr int kWarpedFormatVersion = 4;
/// The first version whose warped beta axis may be whitened (Warp::beta_whitening).
inline constexpr int kWhitenedFormatVersion = 5;
/// The first version with the b-spline interpolation.
inline constexpr int kBSplineFormatVersion = 6;
/// Whether read_table reads law tables of this version: 1, 2, 4, 5 and 6.
bool is_law_table_version(int version) noexcept;

/// How an axis spends its nodes. u in [0, 1] is the index coordinate (node k at u = k/(count-1)),
/// t = (x - min)/(max - min) the normalized coordinate:
///   linear: t = u                      (uniform)
///   sqrt:   t = u^2,  u = sqrt(t)      (dense at min: grazing angles for h and a)
///   cos:    t = (1 - cos(pi u))/2,  u = acos(1 - 2t)/pi   (Chebyshev–Lobatto: dense at both
///           ends; on [-1, 1] this is exactly uniform in the angle theta = pi (1 - u))
///   sinh:   x = c + w sinh(V (2u - 1)),  u = (asinh((x - c)/w)/V + 1)/2, with the centre
///           c = (min + max)/2, the axis' width w (Axis::width) and V = asinh((max - min)/(2w)):
///           dense at the centre on the scale w, spreading geometrically towards both ends (a
///           lobe of angular width w crossing the centre; docs/lut-format.md, version 2)
///   sinh_max: x = max - w sinh(V (1 - u)),  u = 1 - asinh((max - x)/w)/V, V = asinh((max - min)/w):
///           dense at max on the scale w (a lobe reaching the horizon)
enum class Mapping { linear, sqrt, cos, sinh, sinh_max };
const char* to_string(Mapping mapping);
/// Throws InputError naming the value and listing linear, sqrt, cos, sinh.
Mapping parse_mapping(const std::string& text);

/// How a lookup blends nodes (docs/lut-format.md, "Sampling"): multilinear (2 nodes per axis,
/// what a GPU's linear filter does), Catmull–Rom (4 nodes per axis, cubic, C1; at an axis end
/// the missing node is the even reflection for an azimuth, else quadratic extrapolation) or the
/// interpolating cubic B-spline (version 6: 4 coefficients per axis, C2, error ~ h^4 inside; the
/// table stores the spline's coefficients, not the law at the nodes; beyond an axis end the
/// coefficient is the even reflection for an azimuth, else the linear extrapolation 2 c0 - c1,
/// the natural spline; tables/bspline.h). Its four weights are >= 0, so a hardware filter
/// blends them as two linear fetches per axis (Sigg & Hadwiger, GPU Gems 2, ch. 20): 8 in 3-D.
enum class Interpolation { linear, catmull_rom, bspline };
const char* to_string(Interpolation interpolation);  ///< "linear", "catmull-rom" or "b-spline"
/// Accepts "linear", "catmull-rom" and "b-spline"; throws InputError otherwise.
Interpolation parse_interpolation(const std::string& text);
/// The fewest entries of a b-spline axis: 4 nodes (the end conditions' one-sided difference) and
/// the 2 coefficients beyond the ends (tables/bspline.h).
inline constexpr int kBSplineMinCount = 6;
/// The fewest entries per axis a lookup needs: 2 (linear), 4 (Catmull–Rom) or kBSplineMinCount.
constexpr int min_count(Interpolation interpolation) noexcept {
  switch (interpolation) {
    case Interpolation::catmull_rom: return 4;
    case Interpolation::bspline: return kBSplineMinCount;
    case Interpolation::linear: break;
  }
  return 2;
}

/// What the axes of a g table are (docs/lut-format.md, "Axes"):
///   cosines: (i·n, j·n, phi), format version 1's axes;
///   lobe:    (theta_j, psi, beta), relative to the peak p(j) of the model's lobe: theta_j the
///            polar angle of j, psi the angle between i and p, beta the azimuth of i about p
///            measured from the plane of n and p. psi uses the sinh mapping with the lobe's width.
///   warped:  (theta_j, offset, beta) (version 4): psi replaced by the warped offset of the sky's
///            boundary from the lobe, a closed-form approximation of the share of the lobe under
///            the sky, so that g is nearly linear along it (Warp, tables/frame.h).
/// h and a tables always use the cosines frame.
enum class Frame { cosines, lobe, warped };
const char* to_string(Frame frame);  ///< "cosines", "lobe" or "warped"
Frame parse_frame(const std::string& text);

/// Which lookup a table's bound (Table::lookup_error) covers and its exported shader performs
/// (docs/lut-format.md, "Sampling"):
///   texel_fetch: the nodes read one by one and blended in full precision (texelFetch);
///   hardware:    linear blends done by the GPU's texture filter, whose weights a GPU may round
///                to 8 bits (Direct3D and Vulkan guarantee no more sub-texel precision): the
///                bound holds whether the filter rounds those weights to nearest or truncates them.
enum class Filter { texel_fetch, hardware };
const char* to_string(Filter filter);  ///< "texel-fetch" or "hardware"
Filter parse_filter(const std::string& text);
/// The sub-texel precision a hardware filter is held to: weights in steps of 1/256.
inline constexpr double kFilterWeightSteps = 256.0;
/// How a lookup blends: exactly, or as a hardware filter with 8-bit weights rounded to nearest or
/// truncated (the two ends of what GPUs do).
enum class WeightRounding { exact, nearest, truncate };
/// Where the lobe of a lobe-frame table peaks for the viewing direction j: the mirror direction
/// m = 2(j·n)n - j (specular) or j itself (retro: backscatter).
enum class PeakKind { mirror, retro };
const char* to_string(PeakKind peak);  ///< "mirror" or "retro"
PeakKind parse_peak(const std::string& text);

/// How the stored numbers are rounded: IEEE half or single precision (EXR HALF / FLOAT), or
/// unorm16: a 16-bit code u per value, value = offset + scale u / 65535 with the table's offset
/// and scale (Unorm16; docs/lut-format.md, "Encodings"; EXR UINT codes).
enum class Encoding { half, single, unorm16 };
const char* to_string(Encoding encoding);  ///< "half", "float" or "unorm16"
/// Accepts "half", "float" and "unorm16"; throws InputError otherwise.
Encoding parse_encoding(const std::string& text);
/// Bytes of one stored value on a GPU: 2 (half, unorm16) or 4 (float).
unsigned bytes_per_value(Encoding encoding) noexcept;

/// The scale of a unorm16 table: value = offset + scale u / 65535 for the code u in [0, 65535],
/// evaluated in double and rounded to float (a GPU computes the same in float: R16 normalized
/// texels are u / 65535). offset and scale are floats so that a shader holds them exactly.
struct Unorm16 {
  static constexpr double kMaxCode = 65535.0;
  float offset = 0.0f;
  float scale = 0.0f;  ///< >= 0; 0 when every value is the offset
  /// offset <= lo and offset + scale >= hi (both rounded outwards to float), so that rounding
  /// to the nearest code errs by <= scale / 131070 (+ float rounding of the value).
  static Unorm16 covering(double lo, double hi) noexcept;
  float value(std::uint16_t code) const noexcept;
  /// The nearest code to x (clamped to [0, 65535]; 0 for x NaN or scale 0).
  std::uint16_t code(double x) const noexcept;
};

/// One node-centred axis: node 0 is exactly min, node count-1 exactly max.
struct Axis {
  std::string name;
  double min = 0.0;
  double max = 1.0;
  int count = 2;
  Mapping mapping = Mapping::linear;
  double width = 0.0;  ///< the sinh mappings' scale w (> 0); 0 for the other mappings
  bool has_width() const noexcept { return mapping == Mapping::sinh || mapping == Mapping::sinh_max; }

  /// x for the index coordinate u in [0, 1] (clamped).
  double coordinate(double u) const noexcept;
  /// u in [0, 1] for x (x is clamped to [min, max] first): AxisIndex(*this)(x).
  double index_coordinate(double x) const noexcept;
  /// x of node k, exact at both ends.
  double node(int k) const noexcept;

  bool operator==(const Axis&) const = default;  ///< every field: the same nodes
};

/// An axis' index coordinate u(x) with the constants of its mapping computed once: the
/// definition of Axis::index_coordinate, held by a lookup that makes one per axis and point
/// (tables/sample.h, Lookup). With t = (x - min) / (max - min) clamped to [0, 1]:
///   linear: u = t;  sqrt: u = sqrt t;  cos: u = acos(1 - 2t) / pi;  sinh and sinh_max: table.h's
///   inverses above (t itself without a width).
/// Where max - min is a power of two (the cosine axes [-1, 1] and [0, 1], the offset [0, 1]), t is
/// taken as (x - min) times the reciprocal, which is exact there: the same double as the quotient,
/// without a division.
struct AxisIndex {
  AxisIndex() = default;
  explicit AxisIndex(const Axis& axis) noexcept;
  double operator()(double x) const noexcept {
    if (!(range > 0.0)) return 0.0;
    const double offset = x - min;  // NaN -> clamp keeps NaN; caught below
    const double t = std::clamp(exact_reciprocal > 0.0 ? offset * exact_reciprocal : offset / range, 0.0, 1.0);
    if (!(t >= 0.0)) return 0.0;
    switch (mapping) {
      case Mapping::linear: return t;
      case Mapping::sqrt: return std::sqrt(t);
      case Mapping::cos: return util::acos_fast(1.0 - 2.0 * t) / std::numbers::pi;
      case Mapping::sinh:
        if (!(width > 0.0)) return t;
        return std::clamp(0.5 * (std::asinh((min + range * t - centre) / width) / v + 1.0), 0.0, 1.0);
      case Mapping::sinh_max:
        if (!(width > 0.0)) return t;
        return std::clamp(1.0 - std::asinh(range * (1.0 - t) / width) / v, 0.0, 1.0);
    }
    return t;
  }

 private:
  double min = 0.0, range = 0.0;  ///< range = max - min; 0 (or NaN): u = 0
  double exact_reciprocal = 0.0;  ///< 1 / range where range is a power of two (the reciprocal exact), else 0
  Mapping mapping = Mapping::linear;
  double width = 0.0, centre = 0.0, v = 1.0;  ///< the sinh mappings' w, c and V
};

inline double Axis::index_coordinate(double x) const noexcept { return AxisIndex(*this)(x); }

/// Axis names of format version 1.
inline constexpr const char* kAxisCosThetaI = "cos_theta_i";  ///< i·n
inline constexpr const char* kAxisCosThetaJ = "cos_theta_j";  ///< j·n
inline constexpr const char* kAxisPhi = "phi";                ///< azimuth of j minus that of i
/// Axis names of the lobe frame (version 2).
inline constexpr const char* kAxisThetaJ = "theta_j";  ///< polar angle of j, [0, pi/2]
inline constexpr const char* kAxisPsi = "psi";         ///< angle between i and the lobe's peak p(j), [0, pi]
inline constexpr const char* kAxisBeta = "beta";       ///< azimuth of i about p(j), folded to [0, pi]
/// The warped frame's second axis (version 4): the warped offset of the sky's boundary, [0, 1].
inline constexpr const char* kAxisOffset = "offset";

/// The axes of a law for an isotropic model, with the default mappings, given the node counts
/// (g: 3 counts; h, a: 1). Throws InputError for another law, a wrong number of counts or a
/// count below 2.
///   g: cos_theta_i in [-1, 1] (cos), cos_theta_j in [0, 1] (cos), phi in [0, pi] (linear)
///   h: cos_theta_j in [0, 1] (sqrt)
///   a: cos_theta_i in [0, 1] (sqrt)
std::vector<Axis> default_axes(Law law, std::span<const int> counts);

/// default_axes with the mapping of each axis replaced by `mappings[d]` (empty: keep the
/// defaults). Throws InputError when `mappings` is neither empty nor one per axis.
std::vector<Axis> make_axes(Law law, std::span<const int> counts, std::span<const Mapping> mappings);

/// The theta_j axis of the lobe frame is dense towards the horizon on this many lobe widths: where
/// the lobe reaches the horizon, the part of it the horizon hides changes on the scale of the
/// width; away from it g is cos(theta_j) I1 + sin(theta_j) I2 with I1, I2 fixed by (psi, beta),
/// smooth. A narrower band leaves the nodes too sparse near the normal, a linear axis too sparse
/// at grazing (compared on specular alpha = 1000: docs/tradeoff.md).
inline constexpr double kThetaJWidths = 6.0;

/// The axes of a lobe-frame g table with lobe width `width` (radians, > 0) and node counts
/// (theta_j, psi, beta):
///   theta_j in [0, pi/2] (sinh_max, kThetaJWidths x width), psi in [0, pi] (sinh, width),
///   beta in [0, pi] (linear).
/// Throws InputError for a count below 2 or a width that is not a positive finite number.
std::vector<Axis> lobe_axes(std::span<const int> counts, double width);

/// The axes of a warped-frame g table (tables/frame.h) with theta_j's sinh_max width (radians, > 0)
/// and node counts (theta_j, offset, beta): theta_j in [0, pi/2] (sinh_max), offset in [0, 1]
/// (linear), beta in [0, pi] (linear). Throws InputError like lobe_axes.
std::vector<Axis> warped_axes(std::span<const int> counts, double theta_width);

/// Parses "M", "MxM" or "MxMxM" (M = linear, sqrt or cos) into one mapping per axis of the law;
/// a single M stands for every axis; "default" gives the empty list (the law's defaults).
/// Throws InputError naming the text and the expected form.
std::vector<Mapping> parse_mappings(const std::string& text, Law law);

/// The margin of Table::lookup_error over the largest error measured at the validation points:
/// the validation points are a sample, a fresh point may err somewhat more (tests/tables_test.cpp
/// checks the bound holds at >= 99.9% of fresh random points).
inline constexpr double kLookupMargin = 1.5;

/// The warp of a warped-frame table (docs/lut-format.md, "The warped frame"; tables/frame.h):
/// per sample k, at theta_j's index coordinate k/(K - 1), the lobe's centre shift along e1 and its
/// widths along e1 and e2 (gnomonic units), blended linearly in between; the share `mix` of the
/// offset axis that follows the lobe (the rest is uniform in psi); and the envelope's width
/// (0: none): the stored numbers are g / A(theta_j), A = (cos + sqrt(cos^2 + width^2 sin^2))/2.
/// `beta_whitening` mu: the third axis is (1 - mu) beta + mu beta_w, beta_w the edge's direction
/// in the plane where the lobe is round (tables/frame.h, warped_beta); 0: beta itself (files that
/// do not name it).
struct WarpSample {
  double shift = 0.0, along = 1.0, across = 1.0;
  bool operator==(const WarpSample&) const = default;
};
struct Warp {
  std::vector<WarpSample> samples;  ///< >= 2
  double mix = 0.0;                 ///< in (0, 1]
  double envelope = 0.0;            ///< >= 0
  double beta_whitening = 0.0;      ///< in [0, 1)
};

/// The smallest j·n at which a warped table's bound was validated: below it (the last degree
/// and a bit above the horizon) g of microfacet models is nearly discontinuous (the
/// height-correlated visibility layer), and the bound does not claim it. Other tables: 0.
inline constexpr double kWarpedMinCosJ = 0.02;

struct Table {
  Law law = Law::g;
  std::string model;  ///< canonical spec, Model::spec()
  /// Model::content_digest() of the model baked: the bytes of a measured model's data file, whose
  /// path alone (in `model`) does not say what was baked. "" for analytic models, and for tables
  /// written before the attribute existed.
  std::string model_content;
  std::vector<Axis> axes;     ///< slowest first: entry index = ((k0 * n1) + k1) * n2 + k2
  std::vector<float> value;   ///< exactly the stored numbers (half-encoded values are exact floats;
                              ///< a b-spline's coefficients, tables/bspline.h)
  std::vector<float> error;   ///< per-entry bound: cubature estimate + storage rounding, rounded up
  double tolerance = 0.0;     ///< absolute tolerance the cubature was asked for
  double node_error = 0.0;    ///< max of `error`: the nodes' error (cubature + storage rounding)
  long long unconverged = 0;  ///< entries whose cubature missed the tolerance
  /// Largest |lookup - cubature| + the cubature's own error measured after baking at
  /// `interpolation_checks` points the table was not built from (cell centres, and for
  /// validated bakes also seeded random points): measured, not a bound.
  double interpolation_error = 0.0;
  long long interpolation_checks = 0;  ///< 0 for tables made before the measurement existed
  /// THE error of the table: a bound of |lookup - law| anywhere in the domain, validated at the
  /// `interpolation_checks` points (kLookupMargin x interpolation_error, and never below
  /// node_error). Version 1 files: interpolation_error (no margin).
  double lookup_error = 0.0;
  /// The --max-error and --max-bytes the table was baked to (0 and 0 when baked at a given
  /// resolution): part of its cache key.
  double target_error = 0.0;
  std::uint64_t target_bytes = 0;
  int target_fetches = 0;  ///< the --fetches budget it was baked to (0: none)
  std::string command;     ///< the command line that made the table
  std::string version;     ///< ganzfeld version that made it
  Encoding encoding = Encoding::single;
  Unorm16 unorm;  ///< unorm16 only: value[m] = unorm.value(code m) exactly
  Interpolation interpolation = Interpolation::linear;
  Frame frame = Frame::cosines;
  PeakKind peak = PeakKind::mirror;     ///< lobe and warped frames
  Warp warp;                            ///< warped frame only
  Filter filter = Filter::texel_fetch;  ///< the lookup lookup_error covers (version 4; earlier: texel_fetch)
  /// The smallest j·n (g) the bound was validated at (kWarpedMinCosJ for warped tables, else 0).
  double min_cos_j = 0.0;
  int format_version = kFormatVersion;  ///< as read (versions 1, 2) or written
  /// As read: the file's ganzfeld.values_digest, which the reader has checked against `value`
  /// and `error` (values_digest()); "" for files written before it existed. write_table writes
  /// the digest of the numbers it writes, whatever this holds.
  std::string values_digest;

  std::size_t entries() const noexcept;
};

/// Texture fetches one lookup of the table costs a shader (per law), as export/glsl.cpp performs
/// it: texel_fetch reads 2 (linear) or 4 (Catmull–Rom, b-spline) nodes per axis, i.e. 2^D or 4^D;
/// hardware filtering does a linear blend in one fetch, Catmull–Rom in 3 per axis (3^D) and the
/// b-spline in 2 per axis (2^D).
int fetches(const Table& table) noexcept;
/// A --max-error table whose stated lookup error is above its target: only a best-effort bake
/// (BakeOptions::best_effort) keeps one.
bool misses_target(const Table& table) noexcept;
int fetches(Interpolation interpolation, Filter filter, std::size_t dims) noexcept;

/// The digest of the stored numbers (docs/lut-format.md, ganzfeld.values_digest): 64-bit FNV-1a
/// (util/hash.h) of the value then the error entries as little-endian IEEE binary32, e.g.
/// "fnv1a64:0123456789abcdef". Guards against a file's numbers changing under its metadata.
std::string values_digest(const Table& table);

/// Product of the counts; 0 for no axes.
std::uint64_t entry_count(std::span<const Axis> axes) noexcept;
/// Per axis, the step of the entry index between neighbouring nodes along it (Table::axes: the
/// last axis varies fastest, stride 1; each earlier one the product of the later counts).
std::vector<std::size_t> axis_strides(std::span<const Axis> axes);
/// The node count of each axis (a table's resolution, as `--res` and BakeOptions::resolution give it).
std::vector<int> axis_counts(std::span<const Axis> axes);

/// Checks the metadata of a table against its format version (the model spec one printable
/// line, the content digest empty or well-formed, axes of the law and frame, counts, finite
/// numbers, data sizes, finite values, non-negative errors, node_error): throws InputError with
/// a one-line description of the first problem.
void check_table(const Table& table);

}  // namespace ganzfeld::tables
