#include "tables/exr_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <nlohmann/json.hpp>

#include "models/registry.h"
#include "tables/exr_attributes.h"
#include "tables/exr_guard.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace ganzfeld::tables {

namespace fs = std::filesystem;

namespace {

constexpr const char* kValueChannel = "value";
constexpr const char* kErrorChannel = "error";

// Attribute names (docs/lut-format.md, "Header attributes").
constexpr const char* kAttrVersion = "ganzfeld.format_version";
constexpr const char* kAttrModel = "ganzfeld.model";
constexpr const char* kAttrModelContent = "ganzfeld.model_content";  // optional on read: "" when missing
constexpr const char* kAttrLaw = "ganzfeld.law";
constexpr const char* kAttrAxes = "ganzfeld.axes";
constexpr const char* kAttrTolerance = "ganzfeld.tolerance";
constexpr const char* kAttrMaxError = "ganzfeld.max_error";
constexpr const char* kAttrUnconverged = "ganzfeld.unconverged";
constexpr const char* kAttrInterpolationError = "ganzfeld.interpolation_error";    // optional on read
constexpr const char* kAttrInterpolationChecks = "ganzfeld.interpolation_checks";  // optional on read
constexpr const char* kAttrCommand = "ganzfeld.command";
constexpr const char* kAttrGanzfeldVersion = "ganzfeld.version";
constexpr const char* kAttrEncoding = "ganzfeld.encoding";
// Version 2 (all required there, absent in version 1).
constexpr const char* kAttrFrame = "ganzfeld.frame";
constexpr const char* kAttrPeak = "ganzfeld.peak";  // lobe frame only
constexpr const char* kAttrInterpolation = "ganzfeld.interpolation";
constexpr const char* kAttrLookupError = "ganzfeld.lookup_error";
constexpr const char* kAttrTargetError = "ganzfeld.target_error";      // optional: --max-error bakes
constexpr const char* kAttrTargetBytes = "ganzfeld.target_bytes";      // with target_error
constexpr const char* kAttrTargetFetches = "ganzfeld.target_fetches";  // optional: --fetches bakes
// Version 4: the lookup the bound covers, the validated domain, and a warped table's warp.
constexpr const char* kAttrFilter = "ganzfeld.filter";
constexpr const char* kAttrMinCosJ = "ganzfeld.min_cos_j";
constexpr const char* kAttrWarp = "ganzfeld.warp";  // warped frame only
// unorm16 encoding only: value = offset + scale u / 65535 for the UINT code u of the value channel.
constexpr const char* kAttrUnormOffset = "ganzfeld.unorm16_offset";
constexpr const char* kAttrUnormScale = "ganzfeld.unorm16_scale";
// Optional on read (files written before it existed): the digest of the numbers (values_digest).
constexpr const char* kAttrValuesDigest = "ganzfeld.values_digest";

/// The pixel type of the value channel (unorm16: UINT codes) and of the error channel.
Imf::PixelType value_type(Encoding encoding) {
  return encoding == Encoding::half ? Imf::HALF : encoding == Encoding::unorm16 ? Imf::UINT : Imf::FLOAT;
}
Imf::PixelType error_type(Encoding encoding) { return encoding == Encoding::half ? Imf::HALF : Imf::FLOAT; }
const char* type_name(Imf::PixelType type) { return type == Imf::HALF ? "HALF" : type == Imf::UINT ? "UINT" : "FLOAT"; }

/// Image shape: width = count of the last axis, height = product of the others (1 for 1-D).
std::pair<int, int> image_shape(const Table& table) {
  const int width = table.axes.back().count;
  std::uint64_t height = 1;
  for (std::size_t d = 0; d + 1 < table.axes.size(); ++d) height *= static_cast<std::uint64_t>(table.axes[d].count);
  return {width, static_cast<int>(height)};
}

nlohmann::ordered_json axes_json(const Table& table) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (const Axis& axis : table.axes) {
    nlohmann::ordered_json a{{"name", axis.name},
                             {"min", axis.min},
                             {"max", axis.max},
                             {"count", axis.count},
                             {"mapping", to_string(axis.mapping)}};
    if (axis.has_width()) a["width"] = axis.width;
    a["grid"] = "node";
    axes.push_back(a);
  }
  return axes;
}

}  // namespace

std::string warp_text(const Warp& warp) {
  nlohmann::ordered_json samples = nlohmann::ordered_json::array();
  for (const WarpSample& s : warp.samples) samples.push_back({s.shift, s.along, s.across});
  nlohmann::ordered_json doc{{"mix", warp.mix}, {"envelope", warp.envelope}};
  if (warp.beta_whitening != 0.0) doc["beta_whitening"] = warp.beta_whitening;  // absent: 0, as before it existed
  doc["samples"] = samples;
  return doc.dump();
}

void write_table(const Table& table, const std::string& path) {
  check_table(table);  // never write what read_table would refuse
  const auto [width, height] = image_shape(table);
  const bool half = table.encoding == Encoding::half;
  const bool unorm = table.encoding == Encoding::unorm16;
  const Imf::PixelType type = error_type(table.encoding);

  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;  // lossless
  header.channels().insert(kValueChannel, Imf::Channel(value_type(table.encoding)));
  header.channels().insert(kErrorChannel, Imf::Channel(type));
  auto attr = [&](const char* name, const std::string& v) { header.insert(name, Imf::StringAttribute(v)); };
  attr(kAttrVersion, std::to_string(kFormatVersion));
  attr(kAttrModel, table.model);
  attr(kAttrModelContent, table.model_content);
  attr(kAttrLaw, to_string(table.law));
  attr(kAttrAxes, axes_json(table).dump());
  attr(kAttrTolerance, format_number(table.tolerance));
  attr(kAttrMaxError, format_number(table.node_error));
  attr(kAttrUnconverged, std::to_string(table.unconverged));
  attr(kAttrInterpolationError, format_number(table.interpolation_error));
  attr(kAttrInterpolationChecks, std::to_string(table.interpolation_checks));
  attr(kAttrCommand, table.command);
  attr(kAttrGanzfeldVersion, table.version);
  attr(kAttrEncoding, to_string(table.encoding));
  if (unorm) {
    attr(kAttrUnormOffset, format_number(table.unorm.offset));  // shortest text that reads back exactly
    attr(kAttrUnormScale, format_number(table.unorm.scale));
  }
  attr(kAttrFrame, to_string(table.frame));
  if (table.frame != Frame::cosines) attr(kAttrPeak, to_string(table.peak));
  attr(kAttrFilter, to_string(table.filter));
  attr(kAttrMinCosJ, format_number(table.min_cos_j));
  if (table.frame == Frame::warped) attr(kAttrWarp, warp_text(table.warp));
  attr(kAttrInterpolation, to_string(table.interpolation));
  attr(kAttrLookupError, format_number(table.lookup_error));
  if (table.target_error > 0.0) {
    attr(kAttrTargetError, format_number(table.target_error));
    attr(kAttrTargetBytes, std::to_string(table.target_bytes));
    if (table.target_fetches > 0) attr(kAttrTargetFetches, std::to_string(table.target_fetches));
  }
  attr(kAttrValuesDigest, values_digest(table));  // the numbers as read back (check_table: exact in the encoding)

  // Half data are exact in float, so the conversion below loses nothing.
  std::vector<Imath::half> value_half, error_half;
  std::vector<std::uint32_t> codes;
  Imf::FrameBuffer frame;
  const std::size_t stride = half ? sizeof(Imath::half) : sizeof(float);
  if (unorm) {
    for (float v : table.value) codes.push_back(table.unorm.code(v));  // exact: check_table above
    frame.insert(kValueChannel, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(codes.data()), stride, stride * width));
    frame.insert(kErrorChannel, Imf::Slice(type, reinterpret_cast<char*>(const_cast<float*>(table.error.data())),
                                           stride, stride * width));
  } else if (half) {
    value_half.assign(table.value.begin(), table.value.end());
    error_half.assign(table.error.begin(), table.error.end());
    frame.insert(kValueChannel, Imf::Slice(type, reinterpret_cast<char*>(value_half.data()), stride, stride * width));
    frame.insert(kErrorChannel, Imf::Slice(type, reinterpret_cast<char*>(error_half.data()), stride, stride * width));
  } else {
    // OpenEXR's Slice takes a non-const pointer but only reads from it when writing.
    frame.insert(kValueChannel, Imf::Slice(type, reinterpret_cast<char*>(const_cast<float*>(table.value.data())),
                                           stride, stride * width));
    frame.insert(kErrorChannel, Imf::Slice(type, reinterpret_cast<char*>(const_cast<float*>(table.error.data())),
                                           stride, stride * width));
  }

  write_atomically(path, [&, height = height](const std::string& temp) {  // clang < 16: no captured bindings
    std::ofstream os(temp, std::ios::binary | std::ios::trunc);
    if (!os) throw std::runtime_error("cannot create a file in its directory (missing or not writable)");
    {
      Imf::StdOFStream stream(os, temp.c_str());
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    }  // the destructor writes the line-offset table
    os.close();
    if (!os) throw std::runtime_error("the write failed (disk full?)");
  });
}

namespace {

struct Reader : ExrAttributes {
  /// A finite number that a float holds exactly (the unorm16 offset and scale).
  float float_attribute(const Imf::Header& header, const char* name) const {
    const std::string text = attribute(header, name);
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(x) || static_cast<double>(static_cast<float>(x)) != x)
      refuse(std::string(name) + " '" + text + "' is not a finite number a float holds exactly");
    return static_cast<float>(x);
  }

  std::vector<Axis> axes(const std::string& text) const {
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) { refuse(std::string(kAttrAxes) + " is not valid JSON"); }
    if (!doc.is_array()) refuse(std::string(kAttrAxes) + " is not a JSON array of axes");
    std::vector<Axis> out;
    for (const auto& a : doc) {
      const bool ok = a.is_object() && a.contains("name") && a["name"].is_string() && a.contains("min") &&
                      a["min"].is_number() && a.contains("max") && a["max"].is_number() && a.contains("count") &&
                      a["count"].is_number_integer() && a.contains("mapping") && a["mapping"].is_string();
      if (!ok) refuse(std::string(kAttrAxes) + ": each axis needs name, min, max, count (integer), mapping");
      if (a.contains("grid") && a["grid"] != "node")
        refuse("axis grid '" + a["grid"].dump() + "' is not supported; allowed: node");
      const long long count = a["count"].get<long long>();
      if (count < 2 || count > std::numeric_limits<int>::max())
        refuse("axis " + a["name"].get<std::string>() + " has count " + std::to_string(count) +
               "; allowed: 2 to 2^31-1");
      Axis axis;
      axis.name = a["name"].get<std::string>();
      axis.min = a["min"].get<double>();
      axis.max = a["max"].get<double>();
      axis.count = static_cast<int>(count);
      try {
        axis.mapping = parse_mapping(a["mapping"].get<std::string>());
      } catch (const InputError& e) { refuse(e.what()); }
      if (a.contains("width")) {
        if (!a["width"].is_number()) refuse("axis " + axis.name + " has a width that is not a number");
        axis.width = a["width"].get<double>();
      }
      out.push_back(axis);
    }
    return out;
  }

  /// A warped table's warp: {"mix": m, "envelope": w, ["beta_whitening": mu,] "samples": [[shift, along,
  /// across], ...]} (check_table judges the numbers).
  Warp warp(const std::string& text) const {
    const std::string bad = std::string(kAttrWarp) +
                            " is not {\"mix\": number, \"envelope\": number, [\"beta_whitening\": number,] "
                            "\"samples\": [[shift, along, across], ...]}";
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) { refuse(bad); }
    if (!doc.is_object() || !doc.contains("mix") || !doc["mix"].is_number() || !doc.contains("envelope") ||
        !doc["envelope"].is_number() || !doc.contains("samples") || !doc["samples"].is_array() ||
        doc["samples"].size() > 4096 || (doc.contains("beta_whitening") && !doc["beta_whitening"].is_number()))
      refuse(bad);
    Warp w;
    w.mix = doc["mix"].get<double>();
    w.envelope = doc["envelope"].get<double>();
    if (doc.contains("beta_whitening")) w.beta_whitening = doc["beta_whitening"].get<double>();
    for (const auto& s : doc["samples"]) {
      if (!s.is_array() || s.size() != 3 || !s[0].is_number() || !s[1].is_number() || !s[2].is_number()) refuse(bad);
      w.samples.push_back({s[0].get<double>(), s[1].get<double>(), s[2].get<double>()});
    }
    return w;
  }

  /// Law, model (as text), content digest, encoding, axes, tolerance and errors; version first:
  /// a newer format is refused before anything else is judged.
  void read_metadata(const Imf::Header& header, Table& table) const {
    const std::string version = attribute(header, kAttrVersion);
    bool known = false;
    for (int v = kOldestFormatVersion; v <= kFormatVersion; ++v)
      known = known || (is_law_table_version(v) && version == std::to_string(v));
    if (!known)
      refuse("format version '" + version + "' is not supported; this ganzfeld reads law tables of versions 1, 2, " +
             std::to_string(kWarpedFormatVersion) + " to " + std::to_string(kFormatVersion) +
             " (version 3 is a parameter table)");
    table.format_version = std::stoi(version);
    try {
      table.law = parse_law(attribute(header, kAttrLaw));
      // Kept as text, never parsed: a table must read without its model's code or data files
      // (a measured model's file may have moved); check_table checks the text's form.
      table.model = attribute(header, kAttrModel);
      // Tables written before the digest existed have none: they read as analytic ones.
      if (header.findTypedAttribute<Imf::StringAttribute>(kAttrModelContent))
        table.model_content = attribute(header, kAttrModelContent);
      table.encoding = parse_encoding(attribute(header, kAttrEncoding));
    } catch (const InputError& e) { refuse(std::string(e.what())); }
    if (table.encoding == Encoding::unorm16) {
      table.unorm.offset = float_attribute(header, kAttrUnormOffset);
      table.unorm.scale = float_attribute(header, kAttrUnormScale);
    }
    table.axes = axes(attribute(header, kAttrAxes));
    table.tolerance = number(header, kAttrTolerance);
    table.node_error = number(header, kAttrMaxError);
    const double unconverged = number(header, kAttrUnconverged);
    if (unconverged != std::floor(unconverged) || unconverged > 9e18)
      refuse(std::string(kAttrUnconverged) + " is not a count");
    table.unconverged = static_cast<long long>(unconverged);
    if (header.findTypedAttribute<Imf::StringAttribute>(kAttrInterpolationChecks)) {
      const double checks = number(header, kAttrInterpolationChecks);
      table.interpolation_error = number(header, kAttrInterpolationError);
      if (checks != std::floor(checks) || checks < 0 || checks > 9e18 || !(table.interpolation_error >= 0))
        refuse(std::string(kAttrInterpolationChecks) + " / " + kAttrInterpolationError +
               " are not a count and an error");
      table.interpolation_checks = static_cast<long long>(checks);
    }
    if (table.format_version >= 2) read_version_2(header, table);
    else table.lookup_error = table.interpolation_error;  // version 1: measured, no margin
    table.command = attribute(header, kAttrCommand);
    table.version = attribute(header, kAttrGanzfeldVersion);
    if (table.axes.size() != (table.law == Law::g ? 3u : 1u))
      refuse(std::string("law ") + to_string(table.law) + " needs " + (table.law == Law::g ? "3 axes" : "1 axis") +
             " but " + kAttrAxes + " lists " + std::to_string(table.axes.size()));
  }

  /// Format version 2: frame, peak, interpolation, the headline lookup error and a --max-error target.
  void read_version_2(const Imf::Header& header, Table& table) const {
    try {
      table.frame = parse_frame(attribute(header, kAttrFrame));
      if (table.frame != Frame::cosines) table.peak = parse_peak(attribute(header, kAttrPeak));
      table.interpolation = parse_interpolation(attribute(header, kAttrInterpolation));
    } catch (const InputError& e) { refuse(std::string(e.what())); }
    table.lookup_error = number(header, kAttrLookupError);
    if (table.format_version >= kWarpedFormatVersion) {
      try {
        table.filter = parse_filter(attribute(header, kAttrFilter));
      } catch (const InputError& e) { refuse(std::string(e.what())); }
      table.min_cos_j = number(header, kAttrMinCosJ);
      if (table.frame == Frame::warped) table.warp = warp(attribute(header, kAttrWarp));
    }
    if (header.findTypedAttribute<Imf::StringAttribute>(kAttrTargetError)) {
      table.target_error = number(header, kAttrTargetError);
      const double bytes = number(header, kAttrTargetBytes);
      if (bytes != std::floor(bytes) || bytes > 1.8e19) refuse(std::string(kAttrTargetBytes) + " is not a count");
      table.target_bytes = static_cast<std::uint64_t>(bytes);
      if (header.findTypedAttribute<Imf::StringAttribute>(kAttrTargetFetches)) {
        const double budget = number(header, kAttrTargetFetches);
        if (budget != std::floor(budget) || budget < 1 || budget > 1e6)
          refuse(std::string(kAttrTargetFetches) + " is not a count >= 1");
        table.target_fetches = static_cast<int>(budget);
      }
    }
  }

  /// Exactly the channels "value" and "error", of the encoding's pixel types.
  void check_channels(const Imf::Header& header, Encoding encoding) const {
    std::set<std::string> names;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      names.insert(it.name());
      const Imf::PixelType type = it.name() == std::string(kValueChannel) ? value_type(encoding) : error_type(encoding);
      if (it.channel().type != type)
        refuse(std::string("channel '") + it.name() + "' is not " + type_name(type) +
               " as ganzfeld.encoding=" + to_string(encoding) + " says");
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        refuse(std::string("channel '") + it.name() + "' is subsampled");
    }
    if (names != std::set<std::string>{kValueChannel, kErrorChannel}) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      refuse("channels are {" + list + "}; expected exactly {error, value}");
    }
  }

  /// The image's shape against the axes: width = last axis, height = product of the others.
  void check_shape(const Imath::Box2i& window, const std::vector<Axis>& axes) const {
    const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
    long long want_height = 1;
    for (std::size_t d = 0; d + 1 < axes.size(); ++d) {
      want_height *= axes[d].count;
      if (want_height > std::numeric_limits<int>::max()) refuse("the axes describe an absurdly large table");
    }
    if (window.min.x != 0 || window.min.y != 0)
      refuse("data window starts at (" + std::to_string(window.min.x) + ", " + std::to_string(window.min.y) +
             "); expected (0, 0)");
    if (width != axes.back().count || height != want_height)
      refuse("image is " + std::to_string(width) + "x" + std::to_string(height) + " but the axes need " +
             std::to_string(axes.back().count) + "x" + std::to_string(want_height) +
             " (width = count of the last axis, height = product of the others)");
  }

  /// The value and error channels into the table (half converted to float, unorm16 codes to
  /// their values; a code above 65535 is refused).
  void read_pixels(Imf::InputFile& file, const Imath::Box2i& window, Encoding encoding, Table& table) const {
    const Imf::PixelType type = error_type(encoding);
    const std::size_t w = static_cast<std::size_t>(window.max.x - window.min.x + 1);
    const std::size_t n = w * static_cast<std::size_t>(window.max.y - window.min.y + 1);
    table.value.resize(n);
    table.error.resize(n);
    Imf::FrameBuffer frame;
    std::vector<Imath::half> value_half, error_half;
    std::vector<std::uint32_t> codes;
    auto slice = [&](char* base, std::size_t size) { return Imf::Slice(type, base, size, size * w); };
    if (encoding == Encoding::unorm16) {
      codes.resize(n);
      frame.insert(kValueChannel, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(codes.data()), sizeof(std::uint32_t),
                                             sizeof(std::uint32_t) * w));
      frame.insert(kErrorChannel, slice(reinterpret_cast<char*>(table.error.data()), sizeof(float)));
    } else if (type == Imf::HALF) {
      value_half.resize(n);
      error_half.resize(n);
      frame.insert(kValueChannel, slice(reinterpret_cast<char*>(value_half.data()), sizeof(Imath::half)));
      frame.insert(kErrorChannel, slice(reinterpret_cast<char*>(error_half.data()), sizeof(Imath::half)));
    } else {
      frame.insert(kValueChannel, slice(reinterpret_cast<char*>(table.value.data()), sizeof(float)));
      frame.insert(kErrorChannel, slice(reinterpret_cast<char*>(table.error.data()), sizeof(float)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (type == Imf::HALF)
      for (std::size_t m = 0; m < n; ++m) {
        table.value[m] = value_half[m];
        table.error[m] = error_half[m];
      }
    for (std::size_t m = 0; m < codes.size(); ++m) {
      if (codes[m] > Unorm16::kMaxCode)
        refuse("value code " + std::to_string(codes[m]) + " at entry " + std::to_string(m) + " is above 65535");
      table.value[m] = table.unorm.value(static_cast<std::uint16_t>(codes[m]));
    }
  }

  Table read() const {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) refuse("no such file");
    if (!Imf::isOpenExrFile(path.c_str())) refuse("not an OpenEXR file");
    check_exr_sizes(path);  // before OpenEXR allocates what the header declares
    try {
      Imf::InputFile file(path.c_str());
      const Imf::Header& header = file.header();
      Table table;
      read_metadata(header, table);
      check_channels(header, table.encoding);
      check_shape(header.dataWindow(), table.axes);
      if (!file.isComplete()) refuse("truncated file (not all scanlines are present)");
      read_pixels(file, header.dataWindow(), table.encoding, table);
      try {
        check_table(table);
      } catch (const InputError& e) { refuse(e.what()); }
      if (header.findTypedAttribute<Imf::StringAttribute>(kAttrValuesDigest)) {
        table.values_digest = attribute(header, kAttrValuesDigest);
        if (table.values_digest != values_digest(table))
          refuse(std::string("the numbers do not match ") + kAttrValuesDigest + " " + table.values_digest +
                 " (they hash to " + values_digest(table) + "): the file was changed or damaged after it was written");
      }
      return table;
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {  // Iex::BaseExc derives from std::exception
      refuse("unreadable or truncated OpenEXR file: " + std::string(e.what()));
    }
  }
};

}  // namespace

Table read_table(const std::string& path) {
  return Reader{{path, "", "; not a ganzfeld table of format version " + std::to_string(kFormatVersion)}}.read();
}

}  // namespace ganzfeld::tables
