// Format version 3 files (docs/lut-format.md, "Version 3: parameter axes and channels"): one
// scanline OpenEXR image, width = cos_theta_i samples, height = parameter samples, a channel per
// value and one per error bound (NAME and NAME_error), string attributes for the rest. In memory
// every channel is float; a half table's values and errors are already rounded to half by the
// baker, so the conversions to and from HALF files are exact.
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <nlohmann/json.hpp>

#include "models/registry.h"
#include "tables/exr_attributes.h"
#include "tables/exr_guard.h"
#include "tables/param_table.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace ganzfeld::tables {

namespace fs = std::filesystem;

namespace {

constexpr const char* kErrorSuffix = "_error";
/// Every attribute is "ganzfeld." + its key (docs/lut-format.md, "Version 3"), all required.
std::string attribute_name(const char* key) { return std::string("ganzfeld.") + key; }
constexpr const char* kVersion = "format_version";

/// The frame buffer over every channel's value and error vectors (float, row-major).
Imf::FrameBuffer frame_buffer(ParamTable& table) {
  const std::size_t width = static_cast<std::size_t>(table.axes[1].count);
  Imf::FrameBuffer frame;
  auto slice = [&](std::vector<float>& data) {
    return Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data()), sizeof(float), sizeof(float) * width);
  };
  for (Channel& ch : table.channels) {
    frame.insert(ch.name, slice(ch.value));
    frame.insert(ch.name + kErrorSuffix, slice(ch.error));
  }
  return frame;
}

}  // namespace

nlohmann::ordered_json param_axes_json(const ParamTable& table) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (const Axis& a : table.axes)
    axes.push_back({{"name", a.name},
                    {"min", a.min},
                    {"max", a.max},
                    {"count", a.count},
                    {"mapping", to_string(a.mapping)},
                    {"grid", to_string(table.grid)}});
  return axes;
}

void write_param_table(const ParamTable& table, const std::string& path) {
  check_param_table(table);
  const int width = table.axes[1].count, height = table.axes[0].count;
  const Imf::PixelType type = table.encoding == Encoding::half ? Imf::HALF : Imf::FLOAT;
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  const nlohmann::ordered_json axes = param_axes_json(table);
  nlohmann::ordered_json channels = nlohmann::ordered_json::array();
  for (const Channel& ch : table.channels) {
    header.channels().insert(ch.name, Imf::Channel(type));
    header.channels().insert(ch.name + kErrorSuffix, Imf::Channel(type));
    channels.push_back({{"name", ch.name},
                        {"definition", ch.definition},
                        {"unconverged", ch.unconverged},
                        {"lookup_error", ch.lookup_error}});
  }
  auto attr = [&](const char* key, const std::string& v) {
    header.insert(attribute_name(key), Imf::StringAttribute(v));
  };
  attr(kVersion, std::to_string(kParamFormatVersion));
  attr("preset", table.preset);
  attr("layout", table.layout);
  attr("model", table.model);
  attr("axes", axes.dump());
  attr("channels", channels.dump());
  attr("tolerance", format_number(table.tolerance));
  attr("max_error", format_number(table.node_error));
  attr("lookup_error", format_number(table.lookup_error));
  attr("lookup_checks", std::to_string(table.lookup_checks));
  attr("command", table.command);
  attr("version", table.version);
  attr("encoding", to_string(table.encoding));
  ParamTable copy = table;  // Slice wants non-const pointers
  Imf::FrameBuffer frame = frame_buffer(copy);
  // OpenEXR converts HALF channels to float slices when reading, but writes only from slices of
  // the channel's own type: a half table goes out through half copies (exact: already rounded).
  std::vector<std::vector<Imath::half>> halves;
  halves.reserve(2 * table.channels.size());
  if (type == Imf::HALF)
    for (const Channel& ch : table.channels)
      for (const auto& [name, data] : {std::pair{ch.name, &ch.value}, {ch.name + kErrorSuffix, &ch.error}}) {
        halves.emplace_back(data->begin(), data->end());
        frame.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.back().data()), sizeof(Imath::half),
                                      sizeof(Imath::half) * width));
      }
  write_atomically(path, [&](const std::string& temp) {
    Imf::OutputFile file(temp.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  });
}

namespace {

struct ParamReader : ExrAttributes {
  nlohmann::json json_array(const Imf::Header& header, const char* name) const {
    try {
      nlohmann::json doc = nlohmann::json::parse(attribute(header, name));
      if (doc.is_array()) return doc;
    } catch (const nlohmann::json::exception&) {}
    refuse(attribute_name(name) + " is not a JSON array");
  }

  /// Axes and grid from ganzfeld.axes; every axis must name the same grid.
  void read_axes(const Imf::Header& header, ParamTable& table) const {
    std::set<std::string> grids;
    for (const auto& a : json_array(header, "axes")) {
      const bool ok = a.is_object() && a.contains("name") && a["name"].is_string() && a.contains("min") &&
                      a["min"].is_number() && a.contains("max") && a["max"].is_number() && a.contains("count") &&
                      a["count"].is_number_integer() && a.contains("mapping") && a["mapping"].is_string() &&
                      a.contains("grid") && a["grid"].is_string();
      if (!ok) refuse("ganzfeld.axes: each axis needs name, min, max, count (integer), mapping, grid");
      const long long count = a["count"].get<long long>();
      if (count < 2 || count > (1 << 20)) refuse("axis count " + std::to_string(count) + " is outside [2, 2^20]");
      table.axes.push_back({a["name"].get<std::string>(), a["min"].get<double>(), a["max"].get<double>(),
                            static_cast<int>(count), parse_mapping(a["mapping"].get<std::string>())});
      grids.insert(a["grid"].get<std::string>());
    }
    if (grids.size() != 1) refuse("the axes must all name one grid, node or texel");
    table.grid = parse_grid(*grids.begin());
  }

  void read_channels(const Imf::Header& header, ParamTable& table) const {
    std::set<std::string> expected;
    for (const auto& c : json_array(header, "channels")) {
      const bool ok = c.is_object() && c.contains("name") && c["name"].is_string() && c.contains("definition") &&
                      c["definition"].is_string() && c.contains("unconverged") &&
                      c["unconverged"].is_number_integer() && c.contains("lookup_error") &&
                      c["lookup_error"].is_number();
      if (!ok) refuse("ganzfeld.channels: each channel needs name, definition, unconverged (integer), lookup_error");
      Channel ch{c["name"].get<std::string>(),      c["definition"].get<std::string>(), {}, {},
                 c["unconverged"].get<long long>(), c["lookup_error"].get<double>()};
      expected.insert(ch.name);
      expected.insert(ch.name + kErrorSuffix);
      table.channels.push_back(std::move(ch));
    }
    const Imf::PixelType type = table.encoding == Encoding::half ? Imf::HALF : Imf::FLOAT;
    std::set<std::string> present;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      present.insert(it.name());
      if (it.channel().type != type || it.channel().xSampling != 1 || it.channel().ySampling != 1)
        refuse(std::string("channel '") + it.name() + "' is not an unsampled " + to_string(table.encoding) +
               " channel");
    }
    if (present != expected) refuse("the image's channels are not exactly those ganzfeld.channels lists, with _error");
  }

  ParamTable read() const {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) refuse("no such file");
    if (!Imf::isOpenExrFile(path.c_str())) refuse("not an OpenEXR file");
    check_exr_sizes(path);
    try {
      Imf::InputFile file(path.c_str());
      const Imf::Header& header = file.header();
      if (attribute(header, kVersion) != std::to_string(kParamFormatVersion))
        refuse("format version '" + attribute(header, kVersion) + "' is not 3 (a parameter table)");
      ParamTable table;
      table.preset = attribute(header, "preset");
      table.layout = attribute(header, "layout");
      table.model = attribute(header, "model");
      table.encoding = parse_encoding(attribute(header, "encoding"));
      read_axes(header, table);
      read_channels(header, table);
      table.tolerance = number(header, "tolerance");
      table.node_error = number(header, "max_error");
      table.lookup_error = number(header, "lookup_error");
      table.lookup_checks = static_cast<long long>(number(header, "lookup_checks"));
      table.command = attribute(header, "command");
      table.version = attribute(header, "version");
      const Imath::Box2i w = header.dataWindow();
      if (table.axes.size() != 2 || w.min.x != 0 || w.min.y != 0 || w.max.x + 1 != table.axes[1].count ||
          w.max.y + 1 != table.axes[0].count)
        refuse("the image is not (cos_theta_i count) x (parameter count) at origin (0, 0)");
      if (!file.isComplete()) refuse("truncated file (not all scanlines are present)");
      for (Channel& ch : table.channels) {
        ch.value.resize(table.entries());
        ch.error.resize(table.entries());
      }
      file.setFrameBuffer(frame_buffer(table));
      file.readPixels(0, w.max.y);
      check_param_table(table);
      return table;
    } catch (const InputError& e) {
      if (std::string(e.what()).rfind("table '", 0) == 0) throw;
      refuse(e.what());
    } catch (const std::exception& e) { refuse("unreadable or truncated OpenEXR file: " + std::string(e.what())); }
  }
};

}  // namespace

ParamTable read_param_table(const std::string& path) {
  return ParamReader{{path, "ganzfeld.", " (format version 3)"}}.read();
}

int format_version_of(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec) || !Imf::isOpenExrFile(path.c_str())) return 0;
  try {
    check_exr_sizes(path);
    Imf::InputFile file(path.c_str());
    const auto* a = file.header().findTypedAttribute<Imf::StringAttribute>(attribute_name(kVersion));
    if (!a || a->value().size() != 1 || a->value()[0] < '1' || a->value()[0] > '9') return 0;
    return a->value()[0] - '0';
  } catch (const std::exception&) {
    return 0;  // the version reader's own refusal says what is wrong
  }
}

}  // namespace ganzfeld::tables
