#include "tables/table.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "models/registry.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/names.h"

namespace ganzfeld::tables {

void require_tabulated(Law law) {
  if (law != Law::g && law != Law::h && law != Law::a)
    throw InputError(std::string("law '") + to_string(law) + "' has no table; allowed: g, h, a");
}

Law parse_tabulated_law(const std::string& flag, const std::string& text) {
  const Law law = parse_law(text);
  if (law != Law::g && law != Law::h && law != Law::a)
    throw InputError(flag + " '" + text + "' has no table; allowed: g, h, a");
  return law;
}

using std::numbers::pi;

namespace {
using util::EnumName;
constexpr std::array kMappings{EnumName<Mapping>{Mapping::linear, "linear"}, EnumName<Mapping>{Mapping::sqrt, "sqrt"},
                               EnumName<Mapping>{Mapping::cos, "cos"}, EnumName<Mapping>{Mapping::sinh, "sinh"},
                               EnumName<Mapping>{Mapping::sinh_max, "sinh_max"}};
constexpr std::array kInterpolations{EnumName<Interpolation>{Interpolation::linear, "linear"},
                                     EnumName<Interpolation>{Interpolation::catmull_rom, "catmull-rom"},
                                     EnumName<Interpolation>{Interpolation::bspline, "b-spline"}};
constexpr std::array kFrames{EnumName<Frame>{Frame::cosines, "cosines"}, EnumName<Frame>{Frame::lobe, "lobe"},
                             EnumName<Frame>{Frame::warped, "warped"}};
constexpr std::array kFilters{EnumName<Filter>{Filter::texel_fetch, "texel-fetch"},
                              EnumName<Filter>{Filter::hardware, "hardware"}};
constexpr std::array kPeaks{EnumName<PeakKind>{PeakKind::mirror, "mirror"},
                            EnumName<PeakKind>{PeakKind::retro, "retro"}};
constexpr std::array kEncodings{EnumName<Encoding>{Encoding::half, "half"},
                                EnumName<Encoding>{Encoding::single, "float"},
                                EnumName<Encoding>{Encoding::unorm16, "unorm16"}};
}  // namespace

const char* to_string(Mapping mapping) { return util::name_of(kMappings, mapping); }
Mapping parse_mapping(const std::string& text) { return util::parse_name(kMappings, "axis mapping", text); }

const char* to_string(Interpolation interpolation) { return util::name_of(kInterpolations, interpolation); }
Interpolation parse_interpolation(const std::string& text) {
  return util::parse_name(kInterpolations, "interpolation", text);
}

bool is_law_table_version(int version) noexcept {
  return version == 1 || version == 2 || (version >= kWarpedFormatVersion && version <= kFormatVersion);
}

const char* to_string(Frame frame) { return util::name_of(kFrames, frame); }
Frame parse_frame(const std::string& text) { return util::parse_name(kFrames, "frame", text); }

const char* to_string(Filter filter) { return util::name_of(kFilters, filter); }
Filter parse_filter(const std::string& text) { return util::parse_name(kFilters, "lookup filter", text); }

int fetches(Interpolation interpolation, Filter filter, std::size_t dims) noexcept {
  const bool hardware = filter == Filter::hardware;
  const int per_axis = interpolation == Interpolation::catmull_rom ? (hardware ? 3 : 4)
                       : interpolation == Interpolation::bspline   ? (hardware ? 2 : 4)
                                                                   : (hardware ? 1 : 2);
  int n = 1;
  for (std::size_t d = 0; d < dims; ++d) n *= per_axis;
  return n;
}

int fetches(const Table& table) noexcept { return fetches(table.interpolation, table.filter, table.axes.size()); }

bool misses_target(const Table& table) noexcept {
  return table.target_error > 0.0 && table.lookup_error > table.target_error;
}

const char* to_string(PeakKind peak) { return util::name_of(kPeaks, peak); }
PeakKind parse_peak(const std::string& text) { return util::parse_name(kPeaks, "lobe peak", text); }

const char* to_string(Encoding encoding) { return util::name_of(kEncodings, encoding); }
Encoding parse_encoding(const std::string& text) { return util::parse_name(kEncodings, "encoding", text); }

namespace {
/// The sinh mapping's centre c, half range R and V = asinh(R / w).
struct SinhAxis {
  double c, w, V;
  explicit SinhAxis(const Axis& a) noexcept
      : c(0.5 * (a.min + a.max)), w(a.width), V(std::asinh(0.5 * (a.max - a.min) / a.width)) {}
};
}  // namespace

unsigned bytes_per_value(Encoding encoding) noexcept { return encoding == Encoding::single ? 4u : 2u; }

Unorm16 Unorm16::covering(double lo, double hi) noexcept {
  Unorm16 u;
  u.offset = static_cast<float>(lo);
  if (static_cast<double>(u.offset) > lo) u.offset = std::nextafter(u.offset, -std::numeric_limits<float>::infinity());
  u.scale = static_cast<float>(hi - static_cast<double>(u.offset));
  if (static_cast<double>(u.offset) + static_cast<double>(u.scale) < hi)
    u.scale = std::nextafter(u.scale, std::numeric_limits<float>::infinity());
  return u;
}

float Unorm16::value(std::uint16_t code) const noexcept {
  return static_cast<float>(static_cast<double>(offset) + static_cast<double>(scale) * (code / kMaxCode));
}

std::uint16_t Unorm16::code(double x) const noexcept {
  if (!(scale > 0.0f) || !(x == x)) return 0;
  const double u = std::round((x - static_cast<double>(offset)) / static_cast<double>(scale) * kMaxCode);
  return static_cast<std::uint16_t>(std::clamp(u, 0.0, kMaxCode));
}

double Axis::coordinate(double u) const noexcept {
  u = std::clamp(u, 0.0, 1.0);
  double t = u;
  switch (mapping) {
    case Mapping::linear: t = u; break;
    case Mapping::sqrt: t = u * u; break;
    case Mapping::cos: t = 0.5 * (1.0 - std::cos(pi * u)); break;
    case Mapping::sinh: {
      if (!(width > 0.0)) return min + (max - min) * u;
      const SinhAxis s(*this);
      if (u == 0.0) return min;  // exact ends
      if (u == 1.0) return max;
      return std::clamp(s.c + s.w * std::sinh(s.V * (2.0 * u - 1.0)), min, max);
    }
    case Mapping::sinh_max: {
      if (!(width > 0.0)) return min + (max - min) * u;
      if (u == 0.0) return min;
      if (u == 1.0) return max;
      const double V = std::asinh((max - min) / width);
      return std::clamp(max - width * std::sinh(V * (1.0 - u)), min, max);
    }
  }
  return min + (max - min) * t;
}

AxisIndex::AxisIndex(const Axis& axis) noexcept
    : min(axis.min), range(axis.max - axis.min), mapping(axis.mapping), width(axis.width) {
  int exponent = 0;  // range = 2^k exactly when its mantissa is 1/2; then 1/range = 2^-k, exact unless subnormal
  if (range > 0.0 && std::frexp(range, &exponent) == 0.5 && std::isnormal(1.0 / range)) exact_reciprocal = 1.0 / range;
  if (mapping == Mapping::sinh && width > 0.0) {
    const SinhAxis s(axis);
    centre = s.c;
    v = s.V;
  } else if (mapping == Mapping::sinh_max && width > 0.0) {
    v = std::asinh(range / width);
  }
}

double Axis::node(int k) const noexcept {
  if (k <= 0) return min;
  if (k >= count - 1) return max;
  return coordinate(static_cast<double>(k) / (count - 1));
}

namespace {
/// The axes with their node counts set; refuses a wrong number of counts or a count below 2.
std::vector<Axis> with_counts(std::vector<Axis> axes, std::span<const int> counts, const std::string& what) {
  if (counts.size() != axes.size())
    throw InputError(what + " has " + std::to_string(axes.size()) + " axes but " + std::to_string(counts.size()) +
                     " node counts were given");
  for (std::size_t d = 0; d < axes.size(); ++d) {
    if (counts[d] < 2)
      throw InputError("resolution " + std::to_string(counts[d]) + " on axis " + axes[d].name +
                       " is not allowed; each axis needs at least 2 nodes");
    axes[d].count = counts[d];
  }
  return axes;
}
}  // namespace

std::vector<Axis> default_axes(Law law, std::span<const int> counts) {
  std::vector<Axis> axes;
  switch (law) {
    case Law::g:
      axes = {{kAxisCosThetaI, -1.0, 1.0, 0, Mapping::cos},
              {kAxisCosThetaJ, 0.0, 1.0, 0, Mapping::cos},
              {kAxisPhi, 0.0, pi, 0, Mapping::linear}};
      break;
    case Law::h: axes = {{kAxisCosThetaJ, 0.0, 1.0, 0, Mapping::sqrt}}; break;
    case Law::a: axes = {{kAxisCosThetaI, 0.0, 1.0, 0, Mapping::sqrt}}; break;
    default: require_tabulated(law);
  }
  return with_counts(std::move(axes), counts, std::string("law ") + to_string(law));
}

std::vector<Axis> make_axes(Law law, std::span<const int> counts, std::span<const Mapping> mappings) {
  std::vector<Axis> axes = default_axes(law, counts);
  if (mappings.empty()) return axes;
  if (mappings.size() != axes.size())
    throw InputError(std::string("law ") + to_string(law) + " has " + std::to_string(axes.size()) + " axes but " +
                     std::to_string(mappings.size()) + " mappings were given");
  for (std::size_t d = 0; d < axes.size(); ++d) axes[d].mapping = mappings[d];
  return axes;
}

std::vector<Axis> lobe_axes(std::span<const int> counts, double width) {
  if (!std::isfinite(width) || !(width > 0.0))
    throw InputError("lobe width " + format_number(width) + " is not allowed; expected a positive number of radians");
  std::vector<Axis> axes = {{kAxisThetaJ, 0.0, pi / 2, 0, Mapping::sinh_max, kThetaJWidths * width},
                            {kAxisPsi, 0.0, pi, 0, Mapping::sinh, width},
                            {kAxisBeta, 0.0, pi, 0, Mapping::linear}};
  return with_counts(std::move(axes), counts, "a lobe-frame g table");
}

std::vector<Axis> warped_axes(std::span<const int> counts, double theta_width) {
  if (!std::isfinite(theta_width) || !(theta_width > 0.0))
    throw InputError("theta_j width " + format_number(theta_width) +
                     " is not allowed; expected a positive number of radians");
  std::vector<Axis> axes = {{kAxisThetaJ, 0.0, pi / 2, 0, Mapping::sinh_max, theta_width},
                            {kAxisOffset, 0.0, 1.0, 0, Mapping::linear},
                            {kAxisBeta, 0.0, pi, 0, Mapping::linear}};
  return with_counts(std::move(axes), counts, "a warped-frame g table");
}

std::vector<Mapping> parse_mappings(const std::string& text, Law law) {
  const std::size_t count = law == Law::g ? 3 : 1;
  if (text == "default") return {};
  const std::string bad = "mapping '" + text + "' is not valid for law " + to_string(law) + "; expected default, M" +
                          (law == Law::g ? " or MxMxM" : "") + " with M one of linear, sqrt, cos";
  std::vector<Mapping> mappings;
  std::size_t start = 0;
  while (true) {
    const std::size_t x = text.find('x', start);
    const std::string part = text.substr(start, x == std::string::npos ? std::string::npos : x - start);
    if (part != "linear" && part != "sqrt" && part != "cos") throw InputError(bad);
    mappings.push_back(parse_mapping(part));
    if (x == std::string::npos) break;
    start = x + 1;
  }
  if (mappings.size() == 1) mappings.assign(count, mappings[0]);
  if (mappings.size() != count) throw InputError(bad);
  return mappings;
}

std::size_t Table::entries() const noexcept { return static_cast<std::size_t>(entry_count(axes)); }

std::string values_digest(const Table& table) {
  static_assert(std::endian::native == std::endian::little, "the digest hashes the floats' bytes as stored in memory");
  std::uint64_t hash = util::kFnv1aOffsetBasis;
  for (const std::vector<float>* numbers : {&table.value, &table.error})
    hash = util::fnv1a_64({reinterpret_cast<const char*>(numbers->data()), numbers->size() * sizeof(float)}, hash);
  return util::content_digest(hash);
}

std::uint64_t entry_count(std::span<const Axis> axes) noexcept {
  if (axes.empty()) return 0;
  std::uint64_t n = 1;
  for (const Axis& axis : axes) {
    if (axis.count <= 0) return 0;
    n *= static_cast<std::uint64_t>(axis.count);  // counts are validated < 2^31 by the reader and baker
  }
  return n;
}

std::vector<int> axis_counts(std::span<const Axis> axes) {
  std::vector<int> counts;
  for (const Axis& axis : axes) counts.push_back(axis.count);
  return counts;
}

std::vector<std::size_t> axis_strides(std::span<const Axis> axes) {
  std::vector<std::size_t> stride(axes.size(), 1);
  for (std::size_t d = axes.size(); d-- > 1;) stride[d - 1] = stride[d] * axes[d].count;
  return stride;
}

namespace {

/// The model spec is opaque to a table (read_table never parses it), but it must be something a
/// header line and a one-line message can hold.
void check_model_text(const std::string& spec) {
  const bool blank = spec.find_first_not_of(" \t") == std::string::npos;
  std::string shown = spec;
  bool control = false;
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      control = true;
      c = '?';  // keeps the message on one line
    }
  if (blank || control)
    throw InputError("model spec '" + shown + "' is not allowed; expected one non-empty line of printable text");
}

void check_model_content(const std::string& digest) {
  if (!digest.empty() && !util::is_content_digest(digest))
    throw InputError("model content '" + digest +
                     "' is not allowed; expected fnv1a64: and 16 lower-case hex digits, or nothing");
}

}  // namespace

namespace {
/// A unorm16 table's offset and scale are finite (scale >= 0) and every value is exactly one
/// code's value: what the file's codes, a shader and `sample` all read.
void check_unorm16(const Table& table) {
  if (table.encoding != Encoding::unorm16) return;
  const Unorm16& u = table.unorm;
  if (!std::isfinite(u.offset) || !std::isfinite(u.scale) || u.scale < 0.0f ||
      !std::isfinite(static_cast<double>(u.offset) + u.scale))
    throw InputError("unorm16 offset " + format_number(u.offset) + " and scale " + format_number(u.scale) +
                     " are not allowed; expected finite numbers, scale >= 0");
  for (std::size_t m = 0; m < table.value.size(); ++m)
    if (u.value(u.code(table.value[m])) != table.value[m])
      throw InputError("entry " + std::to_string(m) + " has value " + format_number(table.value[m]) +
                       ", not offset + scale u / 65535 for a 16-bit code u");
}
}  // namespace

namespace {
/// A warped table's warp: >= 2 samples of finite shifts and positive finite widths, mix in (0, 1],
/// a finite envelope width >= 0, beta_whitening in [0, 1); other tables have none. The validated domain: j·n >= 0, < 1.
void check_warp(const Table& table) {
  if (!std::isfinite(table.min_cos_j) || table.min_cos_j < 0.0 || table.min_cos_j >= 1.0)
    throw InputError("validated j·n minimum " + format_number(table.min_cos_j) + " is not allowed; expected [0, 1)");
  const Warp& w = table.warp;
  if (table.frame != Frame::warped) {
    if (!w.samples.empty()) throw InputError("only a warped-frame table has a warp");
    return;
  }
  if (w.samples.size() < 2)
    throw InputError("a warped-frame table needs at least 2 warp samples, it has " + std::to_string(w.samples.size()));
  for (const WarpSample& s : w.samples)
    if (!std::isfinite(s.shift) || !std::isfinite(s.along) || !std::isfinite(s.across) || !(s.along > 0.0) ||
        !(s.across > 0.0))
      throw InputError("warp sample (shift " + format_number(s.shift) + ", along " + format_number(s.along) +
                       ", across " + format_number(s.across) + ") is not allowed; expected finite, widths > 0");
  if (!(w.mix > 0.0 && w.mix <= 1.0)) throw InputError("warp mix " + format_number(w.mix) + " is not in (0, 1]");
  if (!std::isfinite(w.envelope) || w.envelope < 0.0)
    throw InputError("warp envelope width " + format_number(w.envelope) + " is not a finite number >= 0");
  if (!(w.beta_whitening >= 0.0 && w.beta_whitening < 1.0))
    throw InputError("warp beta_whitening " + format_number(w.beta_whitening) + " is not in [0, 1)");
}
}  // namespace

void check_table(const Table& table) {
  check_model_text(table.model);
  check_model_content(table.model_content);
  const char* law = to_string(table.law);
  require_tabulated(table.law);
  std::vector<int> counts;
  for (const Axis& axis : table.axes) counts.push_back(axis.count);
  const std::size_t want = table.law == Law::g ? 3 : 1;
  if (table.axes.size() != want)
    throw InputError(std::string("law ") + law + " needs " + std::to_string(want) + " axes, the metadata lists " +
                     std::to_string(table.axes.size()));
  if (table.frame != Frame::cosines && table.law != Law::g)
    throw InputError(std::string("law ") + law + " tables use the cosines frame; only g has a " +
                     to_string(table.frame) + " frame");
  if (table.format_version < kWarpedFormatVersion &&
      (table.frame == Frame::warped || table.filter != Filter::texel_fetch))
    throw InputError("the warped frame and hardware filtering need format version " +
                     std::to_string(kWarpedFormatVersion));
  if (table.format_version < kWhitenedFormatVersion && table.warp.beta_whitening != 0.0)
    throw InputError("a whitened beta axis needs format version " + std::to_string(kWhitenedFormatVersion));
  if (table.format_version < kBSplineFormatVersion && table.interpolation == Interpolation::bspline)
    throw InputError("b-spline interpolation needs format version " + std::to_string(kBSplineFormatVersion));
  check_warp(table);
  if (table.filter == Filter::hardware && table.interpolation == Interpolation::catmull_rom)
    throw InputError("hardware filtering is validated for linear and b-spline lookups only, not " +
                     std::string(to_string(table.interpolation)));
  if (table.format_version == 1 && (table.frame != Frame::cosines || table.interpolation != Interpolation::linear))
    throw InputError("format version 1 has only the cosines frame and linear interpolation");
  const int fewest = min_count(table.interpolation);
  for (const Axis& a : table.axes)
    if (a.count < fewest)
      throw InputError("axis " + a.name + " has " + std::to_string(a.count) + " nodes; " +
                       to_string(table.interpolation) + " interpolation needs at least " + std::to_string(fewest));
  for (const Axis& a : table.axes) {
    if (a.has_width() && !(std::isfinite(a.width) && a.width > 0.0))
      throw InputError("axis " + a.name + " has the sinh mapping with width " + format_number(a.width) +
                       "; expected a positive width");
    if (!a.has_width() && a.width != 0.0)
      throw InputError("axis " + a.name + " has a width but its mapping is " + to_string(a.mapping));
    if (a.has_width() && table.format_version < 2)
      throw InputError("axis " + a.name + ": the " + to_string(a.mapping) + " mapping needs format version 2");
  }
  const std::vector<Axis> expected =
      want != 3                      ? default_axes(table.law, counts)  // checks counts >= 2
      : table.frame == Frame::lobe   ? lobe_axes(counts, table.axes[1].width > 0.0 ? table.axes[1].width : 1.0)
      : table.frame == Frame::warped ? warped_axes(counts, table.axes[0].width > 0.0 ? table.axes[0].width : 1.0)
                                     : default_axes(table.law, counts);
  for (std::size_t d = 0; d < want; ++d) {
    const Axis& a = table.axes[d];
    const Axis& e = expected[d];
    if (a.name != e.name)
      throw InputError(std::string("axis ") + std::to_string(d) + " of law " + law + " is '" + a.name +
                       "'; expected '" + e.name + "'");
    if (a.min != e.min || a.max != e.max)
      throw InputError("axis " + a.name + " spans [" + format_number(a.min) + ", " + format_number(a.max) +
                       "]; expected [" + format_number(e.min) + ", " + format_number(e.max) + "]");
  }
  const std::uint64_t n = entry_count(table.axes);
  if (table.value.size() != n || table.error.size() != n)
    throw InputError("the data holds " + std::to_string(table.value.size()) + " entries but the axes need " +
                     std::to_string(n));
  if (!std::isfinite(table.tolerance) || !(table.tolerance > 0.0))
    throw InputError("tolerance " + format_number(table.tolerance) + " is not a positive finite number");
  if (table.unconverged < 0 || static_cast<std::uint64_t>(table.unconverged) > n)
    throw InputError("unconverged count " + std::to_string(table.unconverged) + " is outside [0, " + std::to_string(n) +
                     "]");
  check_unorm16(table);
  double max_error = 0.0;
  for (std::size_t m = 0; m < n; ++m) {
    if (!std::isfinite(table.value[m]))
      throw InputError("entry " + std::to_string(m) + " has value " + format_number(table.value[m]) +
                       "; every value must be finite");
    if (!std::isfinite(table.error[m]) || table.error[m] < 0.0f)
      throw InputError("entry " + std::to_string(m) + " has error " + format_number(table.error[m]) +
                       "; every error must be finite and >= 0");
    max_error = std::max(max_error, static_cast<double>(table.error[m]));
  }
  if (!std::isfinite(table.lookup_error) || table.lookup_error < 0.0)
    throw InputError("lookup_error " + format_number(table.lookup_error) + " is not a finite number >= 0");
  if (table.node_error != max_error)
    throw InputError("max_error " + format_number(table.node_error) + " disagrees with the error data (max " +
                     format_number(max_error) + ")");
}

}  // namespace ganzfeld::tables
