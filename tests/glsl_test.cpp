// export/glsl and export/texture_file: identifiers, the KTX2 file (round trip, layout, malformed files),
// the C header and the exporter's metadata checks. The shaders themselves are compiled by
// glsl_export_test.sh and run on a real GL implementation by gl_shader_test.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "export/glsl.h"
#include "export/glsl_f.h"
#include "export/texture_file.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "tables/frame.h"
#include "tests/temp_dir.h"
#include "util/error.h"

namespace ganzfeld {
using namespace ganzfeld::tables;
using namespace ganzfeld::exporting;

namespace {

std::string temp_file(const std::string& name) {
  return (std::filesystem::path(testing_support::temp_dir()) / name).string();
}

Table small_table(const std::string& spec, Law law, Encoding encoding) {
  BakeOptions options;
  options.resolution = law == Law::g ? std::vector<int>{5, 4, 3} : std::vector<int>{9};
  options.tolerance = 1e-6;
  options.encoding = encoding;
  Table table = bake(*parse_model(spec), law, options);
  table.command = "test";
  return table;
}

std::uint32_t u32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return b[at] | (b[at + 1] << 8) | (b[at + 2] << 16) | (static_cast<std::uint32_t>(b[at + 3]) << 24);
}

TEST(GlslIdentifier, IsAValidUnreservedGlslName) {
  EXPECT_EQ(glsl_identifier("specular:alpha=8"), "gz_specular_alpha_8");
  EXPECT_EQ(glsl_function_name("minnaert:xi=0.5", Law::h), "gz_minnaert_xi_0_5_h");
  EXPECT_EQ(glsl_sampler_name("asperity:alpha=4", Law::g), "gz_tex_asperity_alpha_4_g");
  // GLSL reserves "__" anywhere in an identifier.
  for (const std::string text : {"a__b", "x::=y", "::lead", "trail::", "hvd-empirical:cd=0.5,f0=0.04"})
    EXPECT_EQ(glsl_identifier(text).find("__"), std::string::npos) << text;
}

TEST(Ktx2, FloatAndHalfTablesRoundTripExactly) {
  for (Encoding encoding : {Encoding::single, Encoding::half}) {
    for (Law law : {Law::g, Law::h}) {
      const Table table = small_table("specular:alpha=8", law, encoding);
      const std::string path = temp_file(std::string("t_") + to_string(law) + to_string(encoding) + ".ktx2");
      write_texture(table, TextureFormat::ktx2, path, "t");
      const TextureData data = read_ktx2(path);
      EXPECT_EQ(data.vk_format, encoding == Encoding::half ? kVkFormatR16Sfloat : kVkFormatR32Sfloat);
      const TextureSize size = texture_size(table);
      EXPECT_EQ(data.size.width, size.width);
      EXPECT_EQ(data.size.height, size.height);
      EXPECT_EQ(data.size.depth, size.depth);
      ASSERT_EQ(data.texels.size(), table.value.size());
      for (std::size_t k = 0; k < table.value.size(); ++k) EXPECT_EQ(data.texels[k], table.value[k]) << k;
      EXPECT_EQ(data.key_values.at("ganzfeld.model"), "specular:alpha=8");
      EXPECT_EQ(data.key_values.at("ganzfeld.law"), to_string(law));
      EXPECT_EQ(data.key_values.count("KTXwriter"), 1u);
    }
  }
}

// unorm16: the KTX2 level holds the codes (R16_UNORM) and the offset and scale that turn a
// texel code/65535 back into the table's value; the GLSL applies the same offset and scale.
TEST(Ktx2, Unorm16TablesCarryTheirCodesOffsetAndScale) {
  for (Law law : {Law::g, Law::h}) {
    const Table table = small_table("specular:alpha=8", law, Encoding::unorm16);
    const std::string path = temp_file(std::string("t_") + to_string(law) + "_unorm16.ktx2");
    write_texture(table, TextureFormat::ktx2, path, "t");
    const TextureData data = read_ktx2(path);
    EXPECT_EQ(data.vk_format, kVkFormatR16Unorm);
    const float offset = std::stof(data.key_values.at("ganzfeld.unorm16_offset"));
    const float scale = std::stof(data.key_values.at("ganzfeld.unorm16_scale"));
    EXPECT_EQ(offset, table.unorm.offset);
    EXPECT_EQ(scale, table.unorm.scale);
    ASSERT_EQ(data.codes.size(), table.value.size());
    for (std::size_t k = 0; k < table.value.size(); ++k) {
      EXPECT_EQ(data.codes[k], table.unorm.code(table.value[k])) << k;
      EXPECT_EQ(table.unorm.value(data.codes[k]), table.value[k]) << k;
    }
    const std::string glsl = glsl_table_snippet(table);
    EXPECT_NE(glsl.find(" * gz_lookup"), std::string::npos) << glsl;  // offset + scale x lookup
    EXPECT_NE(c_header(table, "t").find("static const uint16_t t_texels"), std::string::npos);
  }
}

TEST(Ktx2, CarriesTheVersion2LookupAndItsError) {
  BakeOptions options;
  options.resolution = {5, 6, 4};
  options.tolerance = 1e-6;
  options.interpolation = Interpolation::catmull_rom;
  options.lobe = LobeFrame{PeakKind::retro, 0.1};
  Table table = bake(*parse_model("backscatter:alpha=100"), Law::g, options);
  table.command = "test";
  const std::string path = temp_file("v2.ktx2");
  write_texture(table, TextureFormat::ktx2, path, "t");
  const TextureData data = read_ktx2(path);
  EXPECT_EQ(data.key_values.at("ganzfeld.frame"), "lobe");
  EXPECT_EQ(data.key_values.at("ganzfeld.peak"), "retro");
  EXPECT_EQ(data.key_values.at("ganzfeld.interpolation"), "catmull-rom");
  EXPECT_EQ(std::stod(data.key_values.at("ganzfeld.lookup_error")), table.lookup_error);
  EXPECT_NE(data.key_values.at("ganzfeld.axes").find("psi 0 3.1415926535897931 6 sinh width 0.10000000000000001"),
            std::string::npos)
      << data.key_values.at("ganzfeld.axes");
  const std::string glsl = glsl_table_snippet(table);
  EXPECT_NE(glsl.find("gz_lobe_coordinates(i, j, n, 1.0)"), std::string::npos);  // retro: s = +1
  EXPECT_NE(glsl.find("gz_lookup3_catmull_rom(table, u, ivec3(5, 6, 4), bvec3(false, false, true))"),
            std::string::npos);
}

TEST(Ktx2, LayoutFollowsTheSpecification) {
  const Table table = small_table("asperity:alpha=2", Law::g, Encoding::single);
  const std::vector<std::uint8_t> bytes = ktx2_bytes(table);
  EXPECT_EQ(u32(bytes, 12), kVkFormatR32Sfloat);
  EXPECT_EQ(u32(bytes, 20), 3u);         // width = phi nodes
  EXPECT_EQ(u32(bytes, 24), 4u);         // height = cos_theta_j nodes
  EXPECT_EQ(u32(bytes, 28), 5u);         // depth = cos_theta_i nodes
  EXPECT_EQ(u32(bytes, 48), 80u + 24u);  // dfdByteOffset: after header, index and one level index entry
  EXPECT_EQ(u32(bytes, 52), 44u);        // dfdByteLength: total size + basic block with one sample
  EXPECT_EQ(u32(bytes, 104), 44u);       // dfdTotalSize
  const std::uint32_t level_offset = u32(bytes, 80);
  EXPECT_EQ(level_offset % 4, 0u);
  EXPECT_EQ(u32(bytes, 88), 4u * 60u);  // byteLength
  EXPECT_EQ(bytes.size(), level_offset + 4u * 60u);
  // Key/value entries are sorted by key.
  const std::uint32_t kvd = u32(bytes, 56), kvd_length = u32(bytes, 60);
  std::string previous;
  for (std::size_t at = kvd; at < kvd + kvd_length;) {
    const std::uint32_t length = u32(bytes, at);
    const std::string key(reinterpret_cast<const char*>(&bytes[at + 4]));
    EXPECT_LT(previous, key);
    previous = key;
    at += 4 + ((length + 3) & ~3u);
  }
}

TEST(Ktx2, MalformedFilesAreRefused) {
  const Table table = small_table("asperity:alpha=2", Law::h, Encoding::single);
  const std::vector<std::uint8_t> good = ktx2_bytes(table);
  auto refused = [&](std::vector<std::uint8_t> bytes, const std::string& name) {
    const std::string path = temp_file(name);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    EXPECT_THROW(read_ktx2(path), InputError) << name;
  };
  refused(std::vector<std::uint8_t>(good.begin(), good.end() - 4), "truncated.ktx2");
  auto bad_id = good;
  bad_id[1] = 'X';
  refused(bad_id, "identifier.ktx2");
  auto bad_format = good;
  bad_format[12] = 37;  // VK_FORMAT_R8G8B8A8_UNORM
  refused(bad_format, "format.ktx2");
  refused({}, "empty.ktx2");
  EXPECT_THROW(read_ktx2(temp_file("missing.ktx2")), InputError);
}

TEST(CHeader, HoldsEveryTexelWithItsDimensions) {
  const Table table = small_table("minnaert:xi=1", Law::g, Encoding::single);
  const std::string text = c_header(table, "gz_m");
  EXPECT_NE(text.find("gz_m_width = 3, gz_m_height = 4, gz_m_depth = 5"), std::string::npos);
  EXPECT_NE(text.find("static const float gz_m_texels[60]"), std::string::npos);
  std::size_t commas = 0;
  for (char c : text.substr(text.find("_texels["))) commas += c == ',';
  EXPECT_EQ(commas, 59u);
}

TEST(GlslExport, MismatchedTablesAreRefused) {
  const Table table = small_table("asperity:alpha=2", Law::h, Encoding::single);
  EXPECT_NO_THROW(check_table_is(table, *parse_model("asperity:alpha=2"), Law::h));
  EXPECT_THROW(check_table_is(table, *parse_model("asperity:alpha=2"), Law::g), InputError);
  EXPECT_THROW(check_table_is(table, *parse_model("asperity:alpha=3"), Law::h), InputError);
  Table broken = table;
  broken.value[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(check_table_is(broken, *parse_model("asperity:alpha=2"), Law::h), InputError);
  EXPECT_THROW(glsl_table_function(broken), InputError);
}

// A measured model's table binds by content (tables::same_model), as the cache reuses it:
// the same bytes at another path are the same model, other bytes at the same path are not.
TEST(GlslExport, MeasuredTablesBindByContent) {
  const std::string a = temp_file("a.tab"), b = temp_file("b.tab");
  const std::string grid = "ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n";
  std::ofstream(a) << grid << "0.3 0.3 0.3 0.3 0.3 0.3 0.3 0.3\n";
  std::filesystem::copy_file(a, b);
  const Table table = small_table("tabulated:file=" + a, Law::h, Encoding::single);
  EXPECT_NO_THROW(check_table_is(table, *parse_model("tabulated:file=" + b), Law::h));
  std::ofstream(a, std::ios::trunc) << grid << "0.2 0.2 0.2 0.2 0.2 0.2 0.2 0.2\n";
  EXPECT_THROW(check_table_is(table, *parse_model("tabulated:file=" + a), Law::h), InputError);
}

/// Occurrences of `what` in `text`.
std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(GlslExport, FOfEveryAnalyticModelIsExportedInTheLocalAndTheWorldFrame) {
  // The model's body in its local frame, the world-space function with a tangent, and for an
  // isotropic model the one without (tests/gl_f_test.cpp runs them against the CPU f).
  const std::string f = glsl_model_f(*parse_model("specular:alpha=8"));
  EXPECT_NE(f.find("float gz_f_specular_alpha_8_local(vec3 i, vec3 j)"), std::string::npos) << f;
  EXPECT_NE(f.find("float gz_f_specular_alpha_8(vec3 i, vec3 j, vec3 n, vec3 t)"), std::string::npos) << f;
  EXPECT_NE(f.find("float gz_f_specular_alpha_8(vec3 i, vec3 j, vec3 n)"), std::string::npos) << f;
  const std::string aniso = glsl_model_f(*parse_model("ward-aniso"));
  EXPECT_NE(aniso.find("(vec3 i, vec3 j, vec3 n, vec3 t)"), std::string::npos);
  EXPECT_EQ(aniso.find("(vec3 i, vec3 j, vec3 n)"), std::string::npos) << "an anisotropic f needs its tangent";
  for (const char* spec : {"oren-nayar:sigma=0.3", "hvd-empirical:cd=0.5,f0=0.04,k=0.5,ns=10,nr=10", "cook-torrance"})
    EXPECT_NO_THROW(glsl_model_f(*parse_model(spec))) << spec;
}

TEST(GlslExport, EachHelperIsEmittedOnceInsideItsGuard) {
  const std::string f = glsl_model_f(*parse_model("0.5*specular:alpha=8 + 0.5*phong"));
  EXPECT_EQ(count(f, "#ifndef GZ_HELPER_gz_pow1m"), 1u) << f;
  EXPECT_EQ(count(f, "float gz_pow1m("), 1u) << f;
}

TEST(GlslExport, FOfAMixtureIsTheWeightedSumOfItsLobes) {
  // Each lobe's function once (GLSL refuses a second definition), then the sum with the mixture's
  // normalized weights (models/mixture.h): 1 and 3 become 0.25 and 0.75.
  const std::string f = glsl_model_f(*parse_model("1*specular:alpha=8 + 3*minnaert:xi=1"));
  EXPECT_EQ(count(f, "float gz_f_specular_alpha_8(vec3 i, vec3 j, vec3 n, vec3 t)"), 1u);
  EXPECT_EQ(count(f, "float gz_f_minnaert_xi_1(vec3 i, vec3 j, vec3 n, vec3 t)"), 1u);
  EXPECT_NE(f.find("return 0.25 * gz_f_specular_alpha_8(i, j, n, t) + 0.75 * gz_f_minnaert_xi_1(i, j, n, t);"),
            std::string::npos)
      << f;
  EXPECT_NE(f.find("return 0.25 * gz_f_specular_alpha_8(i, j, n) + 0.75 * gz_f_minnaert_xi_1(i, j, n);"),
            std::string::npos)
      << f;
  const std::string twice = glsl_model_f(*parse_model("0.5*specular:alpha=8 + 0.5*specular:alpha=8"));
  EXPECT_EQ(count(twice, "float gz_f_specular_alpha_8(vec3 i, vec3 j, vec3 n, vec3 t)"), 1u) << twice;
  // A mixture with an anisotropic lobe has only the function with a tangent.
  const std::string aniso = glsl_model_f(*parse_model("0.5*lambert + 0.5*ward-aniso"));
  EXPECT_EQ(count(aniso, "float gz_f_0_5_lambert_0_5_ward_aniso"), 1u) << aniso;
}

TEST(GlslExport, TheFunctionCarriesTheTableMetadataAndItsShape) {
  const Table table = small_table("specular:alpha=8", Law::g, Encoding::single);
  const std::string glsl = glsl_table_snippet(table);
  EXPECT_NE(glsl.find("#ifndef GANZFELD_COMMON_GLSL"), std::string::npos);
  EXPECT_NE(glsl.find("made by: test"), std::string::npos);
  EXPECT_NE(glsl.find("ivec3(5, 4, 3)"), std::string::npos);
  EXPECT_NE(glsl.find("gz_index_cos(gz_cos_theta(i, n), -1.0, 1.0)"), std::string::npos);
  EXPECT_EQ(glsl.find("#version"), std::string::npos);  // a snippet: the including shader picks the version
}

}  // namespace
}  // namespace ganzfeld
