#include "export/texture_file.h"

#include <array>
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <Imath/half.h>

#include "tables/exr_io.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/literal.h"
#include "util/names.h"

namespace ganzfeld::exporting {

using namespace ganzfeld::tables;

namespace {

// KTX 2.0 (Khronos, "KTX File Format Specification", version 2.0): identifier, header,
// index, level index, data format descriptor, key/value data, level data. Little-endian.
constexpr std::uint8_t kKtx2Identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::size_t kHeaderBytes = 12 + 9 * 4 + 4 * 4 + 2 * 8;  // identifier, header, index
constexpr std::size_t kLevelIndexBytes = 3 * 8;

void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
}
void set32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out[at + b] = static_cast<std::uint8_t>(v >> (8 * b));
}
void set64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) out[at + b] = static_cast<std::uint8_t>(v >> (8 * b));
}
std::uint32_t get32(const std::vector<std::uint8_t>& in, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | in[at + b];
  return v;
}
std::uint64_t get64(const std::vector<std::uint8_t>& in, std::size_t at) {
  return get32(in, at) | (static_cast<std::uint64_t>(get32(in, at + 4)) << 32);
}
void pad4(std::vector<std::uint8_t>& out) {
  while (out.size() % 4) out.push_back(0);
}

std::string number_text(double x) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

/// A C and C++ float literal that reads back as x exactly ("0.0f": C has no "0f").
std::string float_literal(float x) { return decimal_literal(x) + "f"; }

std::string axes_text(const Table& table) {
  std::string text;
  for (const Axis& axis : table.axes) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "%s%s %.17g %.17g %d %s", text.empty() ? "" : "; ", axis.name.c_str(),
                  axis.min, axis.max, axis.count, to_string(axis.mapping));
    text += buffer;
    if (axis.has_width()) text += " width " + number_text(axis.width);  // the sinh mappings' scale
  }
  return text;
}

}  // namespace

namespace {
constexpr std::array kTextureFormats{util::EnumName<TextureFormat>{TextureFormat::ktx2, "ktx2"},
                                     util::EnumName<TextureFormat>{TextureFormat::header, "header"}};
}  // namespace

const char* to_string(TextureFormat format) { return util::name_of(kTextureFormats, format); }
TextureFormat parse_texture_format(const std::string& text) {
  return util::parse_name(kTextureFormats, "texture format", text);
}

const char* texture_extension(TextureFormat format) { return format == TextureFormat::ktx2 ? ".ktx2" : ".h"; }

TextureSize texture_size(const Table& table) {
  if (table.axes.size() == 3) return {table.axes[2].count, table.axes[1].count, table.axes[0].count};
  return {table.axes.at(0).count, 1, 1};
}

std::vector<std::uint8_t> ktx2_bytes(const Table& table) {
  check_table(table);
  const bool half = table.encoding == Encoding::half;
  const bool unorm = table.encoding == Encoding::unorm16;
  const std::uint32_t type_size = bytes_per_value(table.encoding);
  const TextureSize size = texture_size(table);
  std::vector<std::uint8_t> out(std::begin(kKtx2Identifier), std::end(kKtx2Identifier));
  put32(out, half ? kVkFormatR16Sfloat : unorm ? kVkFormatR16Unorm : kVkFormatR32Sfloat);
  put32(out, type_size);
  put32(out, static_cast<std::uint32_t>(size.width));
  put32(out, static_cast<std::uint32_t>(size.height));
  put32(out, table.axes.size() == 3 ? static_cast<std::uint32_t>(size.depth) : 0u);  // 0: not a 3-D texture
  put32(out, 0);                                                                     // layerCount: not an array
  put32(out, 1);                                                                     // faceCount
  put32(out, 1);  // levelCount: one level, no mipmaps (the lookup is exact on level 0)
  put32(out, 0);  // supercompressionScheme: none
  const std::size_t index_at = out.size();
  out.resize(kHeaderBytes + kLevelIndexBytes, 0);  // index and level index, filled in below

  // Data format descriptor: one basic block, one float sample (Khronos Data Format 1.3, RGBSDA).
  const std::size_t dfd_at = out.size();
  put32(out, 4 + 24 + 16);               // dfdTotalSize
  put32(out, 0);                         // vendorId = Khronos, descriptorType = basic
  put32(out, 2u | ((24u + 16u) << 16));  // versionNumber 2, descriptorBlockSize
  out.insert(out.end(), {1, 1, 1, 0});   // colorModel RGBSDA, primaries BT.709, transfer linear, flags
  out.insert(out.end(), {0, 0, 0, 0});   // texelBlockDimension (1x1x1x1, stored minus one)
  out.insert(out.end(), {static_cast<std::uint8_t>(type_size), 0, 0, 0, 0, 0, 0, 0});  // bytesPlane
  out.push_back(0);                                                                    // bitOffset (16 bits)
  out.push_back(0);
  out.push_back(static_cast<std::uint8_t>(8 * type_size - 1));  // bitLength - 1
  out.push_back(unorm ? 0x00 : 0x00 | 0x80 | 0x40);             // channel R (| FLOAT | SIGNED)
  out.insert(out.end(), {0, 0, 0, 0});                          // samplePosition
  put32(out, unorm ? 0u : 0xBF800000u);                         // sampleLower: 0 or -1.0f
  put32(out, unorm ? 0xFFFFu : 0x3F800000u);                    // sampleUpper: 65535 or 1.0f
  const std::size_t dfd_length = out.size() - dfd_at;

  // Key/value data, sorted by key (byte order), each entry padded to 4 bytes.
  std::map<std::string, std::string> kv{
      {"KTXwriter", "ganzfeld " + table.version},
      {"ganzfeld.axes", axes_text(table)},
      {"ganzfeld.command", table.command},
      {"ganzfeld.encoding", to_string(table.encoding)},
      {"ganzfeld.format_version", std::to_string(kFormatVersion)},
      {"ganzfeld.frame", to_string(table.frame)},
      {"ganzfeld.interpolation", to_string(table.interpolation)},
      {"ganzfeld.interpolation_error", number_text(table.interpolation_error)},
      {"ganzfeld.lookup_error", number_text(table.lookup_error)},
      {"ganzfeld.law", to_string(table.law)},
      {"ganzfeld.max_error", number_text(table.node_error)},
      {"ganzfeld.model", table.model},
      {"ganzfeld.tolerance", number_text(table.tolerance)},
  };
  if (table.frame != Frame::cosines) kv["ganzfeld.peak"] = to_string(table.peak);
  // What the lookup needs beyond the axes (format version 4, docs/lut-format.md): the filter the
  // bound covers, the validated domain, and a warped table's warp.
  kv["ganzfeld.filter"] = to_string(table.filter);
  kv["ganzfeld.min_cos_j"] = number_text(table.min_cos_j);
  if (table.frame == Frame::warped) kv["ganzfeld.warp"] = warp_text(table.warp);
  if (unorm) {  // value = offset + scale x texel (docs/lut-format.md)
    kv["ganzfeld.unorm16_offset"] = number_text(table.unorm.offset);
    kv["ganzfeld.unorm16_scale"] = number_text(table.unorm.scale);
  }
  const std::size_t kvd_at = out.size();
  for (const auto& [key, value] : kv) {
    put32(out, static_cast<std::uint32_t>(key.size() + 1 + value.size() + 1));
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.push_back(0);
    pad4(out);
  }
  const std::size_t kvd_length = out.size() - kvd_at;

  pad4(out);  // level data aligned to lcm(texel size, 4)
  const std::size_t level_at = out.size();
  for (float v : table.value) {
    if (half || unorm) {
      const std::uint16_t bits = unorm ? table.unorm.code(v) : Imath::half(v).bits();
      out.push_back(static_cast<std::uint8_t>(bits));
      out.push_back(static_cast<std::uint8_t>(bits >> 8));
    } else {
      put32(out, std::bit_cast<std::uint32_t>(v));
    }
  }
  const std::size_t level_length = out.size() - level_at;

  set32(out, index_at + 0, static_cast<std::uint32_t>(dfd_at));
  set32(out, index_at + 4, static_cast<std::uint32_t>(dfd_length));
  set32(out, index_at + 8, static_cast<std::uint32_t>(kvd_at));
  set32(out, index_at + 12, static_cast<std::uint32_t>(kvd_length));
  set64(out, index_at + 16, 0);  // no supercompression global data
  set64(out, index_at + 24, 0);
  set64(out, kHeaderBytes + 0, level_at);
  set64(out, kHeaderBytes + 8, level_length);
  set64(out, kHeaderBytes + 16, level_length);
  return out;
}

TextureData read_ktx2(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read texture '" + path + "'");
  return parse_ktx2(std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()),
                    path);
}

TextureData parse_ktx2(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  auto fail = [&](const std::string& why) { return InputError("not a ganzfeld KTX2 texture '" + name + "': " + why); };
  if (bytes.size() < kHeaderBytes + kLevelIndexBytes || std::memcmp(bytes.data(), kKtx2Identifier, 12) != 0)
    throw fail("no KTX 2.0 identifier");
  TextureData data;
  data.vk_format = get32(bytes, 12);
  const std::uint32_t type_size = get32(bytes, 16);
  const bool unorm = data.vk_format == kVkFormatR16Unorm && type_size == 2;
  if (!((data.vk_format == kVkFormatR32Sfloat && type_size == 4) ||
        (data.vk_format == kVkFormatR16Sfloat && type_size == 2) || unorm))
    throw fail("vkFormat " + std::to_string(data.vk_format) + " with typeSize " + std::to_string(type_size) +
               "; allowed: 100 (R32_SFLOAT, 4), 76 (R16_SFLOAT, 2) or 70 (R16_UNORM, 2)");
  const std::uint32_t w = get32(bytes, 20), h = get32(bytes, 24), d = get32(bytes, 28);
  if (get32(bytes, 32) != 0 || get32(bytes, 36) != 1 || get32(bytes, 40) != 1 || get32(bytes, 44) != 0)
    throw fail("layers, faces, levels or supercompression other than 0, 1, 1, none");
  if (w == 0 || h == 0 || w > (1u << 16) || h > (1u << 16) || d > (1u << 16)) throw fail("bad dimensions");
  data.size = {static_cast<int>(w), static_cast<int>(h), d == 0 ? 1 : static_cast<int>(d)};
  const std::uint32_t kvd_at = get32(bytes, 56), kvd_length = get32(bytes, 60);
  const std::uint64_t level_at = get64(bytes, kHeaderBytes), level_length = get64(bytes, kHeaderBytes + 8);
  const std::uint64_t texels = std::uint64_t{w} * h * data.size.depth;
  if (level_length != texels * type_size || level_at > bytes.size() || bytes.size() - level_at < level_length)
    throw fail("level data of " + std::to_string(level_length) + " bytes at " + std::to_string(level_at) +
               " does not hold " + std::to_string(texels) + " texels in a file of " + std::to_string(bytes.size()) +
               " bytes");
  if (kvd_at > bytes.size() || bytes.size() - kvd_at < kvd_length) throw fail("key/value data outside the file");
  for (std::size_t at = kvd_at; at + 4 <= std::size_t{kvd_at} + kvd_length;) {
    const std::uint32_t length = get32(bytes, at);
    if (length > kvd_at + kvd_length - at - 4) throw fail("truncated key/value entry");
    const std::string entry(bytes.begin() + at + 4, bytes.begin() + at + 4 + length);
    const std::size_t zero = entry.find('\0');
    if (zero == std::string::npos) throw fail("key without terminating NUL");
    std::string value = entry.substr(zero + 1);
    if (!value.empty() && value.back() == '\0') value.pop_back();
    data.key_values[entry.substr(0, zero)] = value;
    at += 4 + ((length + 3) & ~3u);
  }
  data.texels.resize(texels);
  for (std::uint64_t k = 0; k < texels; ++k) {
    if (type_size == 4) {
      data.texels[k] = std::bit_cast<float>(get32(bytes, level_at + 4 * k));
      continue;
    }
    const auto bits = static_cast<std::uint16_t>(bytes[level_at + 2 * k] | (bytes[level_at + 2 * k + 1] << 8));
    if (unorm) {
      data.codes.push_back(bits);
      data.texels[k] = static_cast<float>(bits / tables::Unorm16::kMaxCode);
    } else {
      Imath::half value;
      value.setBits(bits);
      data.texels[k] = static_cast<float>(value);
    }
  }
  return data;
}

std::string c_header(const Table& table, const std::string& symbol) {
  check_table(table);
  const bool half = table.encoding == Encoding::half;
  const bool unorm = table.encoding == Encoding::unorm16;
  const TextureSize size = texture_size(table);
  const std::string upload =
      unorm ? "16-bit codes (upload as GL_R16 / GL_UNSIGNED_SHORT; value = " + number_text(table.unorm.offset) + " + " +
                  number_text(table.unorm.scale) + " x texel, texel = code / 65535)"
      : half ? "IEEE half bits (upload as GL_R16F / GL_HALF_FLOAT)"
             : "float (upload as GL_R32F / GL_FLOAT)";
  std::ostringstream s;
  s << "// ganzfeld table as a C array (generated; docs/shaders.md): law " << to_string(table.law) << " of "
    << table.model << "\n// made by: " << table.command << "\n// axes: " << axes_text(table) << "\n// frame "
    << to_string(table.frame)
    << (table.frame == Frame::lobe ? std::string(" (peak ") + to_string(table.peak) + ")" : "") << ", "
    << to_string(table.interpolation) << " lookup (export-glsl's GLSL implements it)"
    << "\n// error: lookup <= " << number_text(table.lookup_error) << "; nodes <= " << number_text(table.node_error)
    << ", between nodes (measured) <= " << number_text(table.interpolation_error)
    << "\n// texels: x (width) fastest, then y (height), then z (depth); " << upload << "\n"
    << "#pragma once\n#include <stdint.h>\n\n"
    << "enum { " << symbol << "_width = " << size.width << ", " << symbol << "_height = " << size.height << ", "
    << symbol << "_depth = " << size.depth << " };\n";
  if (unorm)
    s << "static const float " << symbol << "_unorm16_offset = " << float_literal(table.unorm.offset) << ", " << symbol
      << "_unorm16_scale = " << float_literal(table.unorm.scale) << ";  // value = offset + scale x code / 65535\n";
  s << "static const " << (half || unorm ? "uint16_t " : "float ") << symbol << "_texels[" << table.value.size()
    << "] = {";
  for (std::size_t k = 0; k < table.value.size(); ++k) {
    char buffer[40];
    if (unorm) std::snprintf(buffer, sizeof buffer, "%u", static_cast<unsigned>(table.unorm.code(table.value[k])));
    else if (half) std::snprintf(buffer, sizeof buffer, "0x%04x", Imath::half(table.value[k]).bits());
    const std::string text = half || unorm ? std::string(buffer) : float_literal(table.value[k]);
    s << (k % 8 == 0 ? "\n  " : " ") << text << (k + 1 < table.value.size() ? "," : "");
  }
  s << "\n};\n";
  return s.str();
}

void write_texture(const Table& table, TextureFormat format, const std::string& path, const std::string& symbol) {
  if (format == TextureFormat::header) {
    write_text_atomically(path, c_header(table, symbol), "texture");
    return;
  }
  const std::vector<std::uint8_t> bytes = ktx2_bytes(table);
  write_atomically(
      path,
      [&](const std::string& temp) {
        std::ofstream out(temp, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        if (!out.flush()) throw std::runtime_error("write failed");
      },
      "texture");
}

}  // namespace ganzfeld::exporting
