// A table's values as a texture file for real-time engines (docs/shaders.md):
//   KTX2 (Khronos; what glTF/Vulkan/GL engines load): one mip level, one channel,
//         VK_FORMAT_R32_SFLOAT for float tables, VK_FORMAT_R16_SFLOAT for half tables,
//         VK_FORMAT_R16_UNORM for unorm16 tables (the codes; "ganzfeld.unorm16_offset" and
//         "ganzfeld.unorm16_scale" give value = offset + scale x texel);
//         g tables are 3-D textures (width = phi, height = cos_theta_j, depth = cos_theta_i),
//         h and a tables 2-D textures of height 1; the table's metadata in key/value data
//         ("ganzfeld.model", "ganzfeld.law", "ganzfeld.axes", "ganzfeld.max_error", ...).
//   C header: the same texels as a static array plus the dimensions, for engines that embed
//         tables in their binaries.
// One channel needs no padding: R32F and R16F are core in GL 3.0+ and GLSL ES 3.00 targets.
// Only the values are exported; the per-entry error stays in the EXR.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tables/table.h"

namespace ganzfeld::exporting {

enum class TextureFormat { ktx2, header };
const char* to_string(TextureFormat format);  ///< "ktx2" or "header"
/// Accepts "ktx2" and "header"; throws InputError otherwise.
TextureFormat parse_texture_format(const std::string& text);
/// The file extension of a format, with the dot: ".ktx2" or ".h".
const char* texture_extension(TextureFormat format);

/// Texture dimensions of a table: {width, height, depth} (depth 1 for h and a).
struct TextureSize {
  int width = 1, height = 1, depth = 1;
};
TextureSize texture_size(const tables::Table& table);

/// Vulkan format numbers written to KTX2.
inline constexpr std::uint32_t kVkFormatR16Unorm = 70;
inline constexpr std::uint32_t kVkFormatR16Sfloat = 76;
inline constexpr std::uint32_t kVkFormatR32Sfloat = 100;

/// The KTX2 file of a table (checked with check_table first).
std::vector<std::uint8_t> ktx2_bytes(const tables::Table& table);

/// What read_ktx2 returns: the texels as floats (half texels converted exactly).
struct TextureData {
  std::uint32_t vk_format = 0;
  TextureSize size;
  std::vector<float> texels;         ///< x fastest, then y, then z (R16_UNORM: code / 65535, as a GPU reads it)
  std::vector<std::uint16_t> codes;  ///< R16_UNORM only: the codes, in the order of texels
  std::map<std::string, std::string> key_values;
};
/// Reads the KTX2 files ktx2_bytes writes (one level, R16/R32 SFLOAT or R16 UNORM, no supercompression);
/// throws InputError naming the file and the first problem for anything else.
TextureData read_ktx2(const std::string& path);
/// read_ktx2 of a file's bytes; `name` names it in the messages.
TextureData parse_ktx2(const std::vector<std::uint8_t>& bytes, const std::string& name);

/// The C header: metadata comment, dimensions and texels of `table` under the prefix `symbol`.
std::string c_header(const tables::Table& table, const std::string& symbol);

/// Writes the table as `format` to `path` atomically.
void write_texture(const tables::Table& table, TextureFormat format, const std::string& path,
                   const std::string& symbol);

}  // namespace ganzfeld::exporting
