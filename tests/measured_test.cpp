// Measured BRDFs (models/measured.h) and the generator that writes any model as measured data
// (export/brdf_export.h): the MERL reader round-trips the generator, refuses malformed files, and
// our tabulated format round-trips and refuses malformed text.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "export/brdf_export.h"
#include "integrate/laws.h"
#include "models/measured.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "tables/sample.h"
#include "tests/temp_dir.h"
#include "util/error.h"
#include "util/hash.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

std::string temp_file(const std::string& name) {
  return (std::filesystem::path(testing_support::temp_dir()) / name).string();
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

Vec3 random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = u(rng), phi = 2.0 * pi * u(rng), s = std::sqrt(1.0 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

TEST(MerlAngles, HalfDiffAndDirectionsAreInverse) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 1000; ++n) {
    const merl::HalfDiff a{u(rng) * pi / 2, u(rng) * pi / 2, (2.0 * u(rng) - 1.0) * pi * 0.999};
    const auto [i, j] = merl::directions(a);
    const merl::HalfDiff b = merl::half_diff(i, j);
    EXPECT_NEAR(b.theta_h, a.theta_h, 1e-9);
    EXPECT_NEAR(b.theta_d, a.theta_d, 1e-9);
    if (a.theta_d > 1e-3) { EXPECT_NEAR(b.phi_d, a.phi_d, 1e-7); }
    EXPECT_NEAR(glm::length(i), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(j), 1.0, 1e-12);
  }
}

class MerlRoundTrip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    exporting::write_merl(*parse_model("lambert"), temp_file("lambert.binary"));
    exporting::write_merl(*parse_model("cook-torrance:kd=0.2,ks=0.6,m=0.3"), temp_file("ct.binary"));
  }
};

TEST_F(MerlRoundTrip, FileLayoutAndChannelScales) {
  std::ifstream in(temp_file("ct.binary"), std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), merl::kFileBytes);
  std::int32_t dims[3];
  std::memcpy(dims, bytes.data(), 12);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  // Node (10, 20, 30): the stored numbers are f / scale per channel.
  const ModelPtr ct = parse_model("cook-torrance:kd=0.2,ks=0.6,m=0.3");
  const auto [i, j] = merl::directions(merl::node_angles(10, 20, 30));
  const std::size_t index = (10 * 90 + 20) * 180 + 30;
  for (int c = 0; c < 3; ++c) {
    double stored;
    std::memcpy(&stored, bytes.data() + 12 + (c * merl::kSamples + index) * 8, 8);
    EXPECT_NEAR(stored * merl::kScale[c], ct->f(i, j), 1e-14 * ct->f(i, j));
  }
}

TEST_F(MerlRoundTrip, LambertIsExactEverywhere) {
  for (int lookup : {0, 1}) {
    const ModelPtr m = parse_model("merl:file=" + temp_file("lambert.binary") + ",lookup=" + std::to_string(lookup));
    std::mt19937_64 rng(2);
    for (int n = 0; n < 2000; ++n) {
      const Vec3 i = random_direction(rng), j = random_direction(rng);
      EXPECT_NEAR(m->f(i, j), 1.0 / pi, 1e-14) << "lookup " << lookup;
    }
  }
}

TEST_F(MerlRoundTrip, NodesAreExactAndLookupsConverge) {
  const ModelPtr ct = parse_model("cook-torrance:kd=0.2,ks=0.6,m=0.3");
  const ModelPtr trilinear = parse_model("merl:file=" + temp_file("ct.binary"));
  const ModelPtr truncated = parse_model("merl:file=" + temp_file("ct.binary") + ",lookup=0");
  for (int kh : {0, 5, 30, 60})
    for (int kd : {0, 10, 40})
      for (int kp : {0, 45, 90, 179}) {
        const auto [i, j] = merl::directions(merl::node_angles(kh, kd, kp));
        if (i.z < 0.0 || j.z < 0.0) continue;
        EXPECT_NEAR(trilinear->f(i, j), ct->f(i, j), 1e-9 * ct->f(i, j)) << kh << " " << kd << " " << kp;
      }
  // Between nodes: multilinear is far closer to the model than MERL's truncation.
  std::mt19937_64 rng(3);
  double err_tri = 0.0, err_trunc = 0.0;
  int count = 0;
  for (int n = 0; n < 4000; ++n) {
    const Vec3 i = random_direction(rng), j = random_direction(rng);
    if (i.z < 0.05 || j.z < 0.05) continue;
    const double want = ct->f(i, j);
    err_tri += std::abs(trilinear->f(i, j) - want) / want;
    err_trunc += std::abs(truncated->f(i, j) - want) / want;
    ++count;
  }
  EXPECT_LT(err_tri / count, 0.01);
  EXPECT_LT(err_tri, 0.5 * err_trunc);
  // Through the engine: h of the data matches h of the model to the grid's resolution.
  CubatureOptions options;
  options.abs_tol = 1e-6;
  const Vec3 view{std::sin(0.5), 0.0, std::cos(0.5)};
  // Measured difference 1.9e-5 (the data's interpolation error integrated; each h to 1e-6):
  // 5e-5 leaves room for neither a wrong lookup nor a wrong channel scale (2e-3 did).
  EXPECT_NEAR(darkening(*trilinear, view, options).value, darkening(*ct, view, options).value, 5e-5);
}

TEST(MerlReader, RefusesMalformedFiles) {
  std::vector<char> bytes = exporting::merl_bytes(*parse_model("lambert"));
  auto refused = [&](const std::vector<char>& b, const std::string& name, const std::string& fragment) {
    const std::string path = temp_file(name);
    write_bytes(path, b);
    try {
      parse_model("merl:file=" + path);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) { EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what(); }
  };
  refused(std::vector<char>(bytes.begin(), bytes.end() - 8), "truncated.binary", "bytes");
  std::vector<char> dims = bytes;
  const std::int32_t wrong = 45;
  std::memcpy(dims.data() + 4, &wrong, 4);
  refused(dims, "dims.binary", "90x45x180");
  std::vector<char> nan = bytes;
  const double q = std::nan("");
  std::memcpy(nan.data() + 12 + 8 * 1000, &q, 8);
  refused(nan, "nan.binary", "non-finite");
  refused({}, "empty.binary", "bytes");
  EXPECT_THROW(parse_model("merl:file=" + temp_file("missing.binary")), InputError);
  EXPECT_THROW(parse_model("merl"), InputError);  // file= is required
  EXPECT_THROW(parse_model("merl:channel=1"), InputError);
  EXPECT_THROW(parse_model("merl:file=a,file=b"), InputError);     // twice
  EXPECT_THROW(parse_model("merl:file=x,channel=4"), InputError);  // out of range before reading
}

TEST(MerlReader, InvalidSamplesAreLeftOut) {
  // A file whose nodes are all invalid except one cell reads as 0 outside, never as -1/1500.
  std::vector<char> bytes = exporting::merl_bytes(*parse_model("lambert"));
  const double invalid = -1.0;
  for (std::size_t k = 0; k < 3 * merl::kSamples; k += 2) std::memcpy(bytes.data() + 12 + 8 * k, &invalid, 8);
  write_bytes(temp_file("holes.binary"), bytes);
  const ModelPtr m = parse_model("merl:file=" + temp_file("holes.binary"));
  std::mt19937_64 rng(4);
  for (int n = 0; n < 500; ++n) {
    const double v = m->f(random_direction(rng), random_direction(rng));
    EXPECT_TRUE(v == 0.0 || std::abs(v - 1.0 / pi) < 1e-12) << v;
  }
}

TEST(Tabulated, RoundTripsAndInterpolates) {
  const ModelPtr model = parse_model("minnaert:xi=0.5");
  const std::string path = temp_file("minnaert.tab");
  exporting::write_tabulated(*model, {31, 31, 19}, path);
  const ModelPtr table = parse_model("tabulated:file=" + path);
  const ModelPtr nearest = parse_model("tabulated:file=" + path + ",lookup=0");
  // Nodes are exact (every 3 degrees in theta, 10 in phi).
  const double rad = pi / 180.0;
  for (double ti : {0.0, 30.0, 63.0})
    for (double tr : {3.0, 45.0, 87.0}) {
      const Vec3 i{std::sin(ti * rad), 0, std::cos(ti * rad)}, j{-std::sin(tr * rad), 0, std::cos(tr * rad)};
      EXPECT_NEAR(table->f(i, j), model->f(i, j), 1e-12);
      EXPECT_NEAR(nearest->f(i, j), model->f(i, j), 1e-12);
    }
  std::mt19937_64 rng(6);
  for (int n = 0; n < 500; ++n) {
    const Vec3 i = random_direction(rng), j = random_direction(rng);
    if (i.z < 0.1 || j.z < 0.1) continue;                 // (mu_i mu_j)^0.5 is steep at grazing: no claim there
    EXPECT_NEAR(table->f(i, j), model->f(i, j), 1.5e-3);  // measured worst 7.5e-4 on these 500 pairs
  }
}

TEST(Tabulated, RefusesMalformedText) {
  const std::string good = "ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n1 1 1 1 1 1 1 1\n";
  EXPECT_NO_THROW(parse_tabulated(good, "good"));
  auto refused = [](const std::string& text, const std::string& fragment) {
    try {
      parse_tabulated(text, "t");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) { EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what(); }
  };
  refused("brdf 1\n", "first line");
  refused("ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 90 0\nphi: 0 180\n1 1 1 1 1 1 1 1\n", "increase");
  refused("ganzfeld-tabulated-brdf 1\ntheta_i: 0 95\ntheta_r: 0 90\nphi: 0 180\n1 1 1 1 1 1 1 1\n", "outside");
  refused("ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n1 1 1 1 1 1 1\n", "needs 8");
  refused("ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n1 1 1 -1 1 1 1 1\n", ">= 0");
  refused("ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n1 1 x 1 1 1 1 1\n", "not a number");
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Measured models name their data by its bytes (the cache keys them by it).
TEST(MeasuredContent, DigestIsTheFileBytes) {
  const std::string merl = temp_file("digest.binary"), tab = temp_file("digest.tab"), bm = temp_file("digest.fs");
  exporting::write_merl(*parse_model("lambert"), merl);
  exporting::write_tabulated(*parse_model("lambert"), {3, 3, 3}, tab);
  std::ofstream(bm) << "ganzfeld-beard-maxwell-first-surface 1\ntheta_N: 0 30\nrho_fs: 2 1\n";
  for (const std::string& spec : {"merl:file=" + merl, "tabulated:file=" + tab, "beard-maxwell:file=" + bm}) {
    EXPECT_EQ(parse_model(spec)->content_digest(),
              util::content_digest_of(file_bytes(parse_spec(spec).terms[0].model.file)))
        << spec;
  }
  EXPECT_EQ(parse_model("lambert")->content_digest(), "");
  EXPECT_EQ(parse_model("beard-maxwell")->content_digest(), "");  // the built-in first surface
  EXPECT_EQ(parse_model("0.5*lambert + 0.5*specular:alpha=8")->content_digest(), "");
  // A mixture's digest depends on every lobe's data and on which lobe holds it.
  const std::string with = parse_model("0.5*lambert + 0.5*tabulated:file=" + tab)->content_digest();
  EXPECT_TRUE(util::is_content_digest(with)) << with;
  EXPECT_NE(with, parse_model("0.5*tabulated:file=" + tab + " + 0.5*lambert")->content_digest());
}

TEST(MeasuredContent, SpecWithoutPaths) {
  EXPECT_EQ(spec_without_paths("merl:file=/a:b/c.binary,channel=3,lookup=1"), "merl:channel=3,lookup=1");
  EXPECT_EQ(spec_without_paths("tabulated:lookup=1,file=x.tab"), "tabulated:lookup=1");
  EXPECT_EQ(spec_without_paths("specular:alpha=8"), "specular:alpha=8");
  EXPECT_EQ(spec_without_paths("lambert"), "lambert");
  EXPECT_EQ(spec_without_paths("0.5*lambert + 0.5*tabulated:file=m.tab,lookup=1 + 1e+0*specular:alpha=8"),
            "0.25*lambert + 0.25*tabulated:lookup=1 + 0.5*specular:alpha=8");
}

// A table is self-describing: once baked it reads and samples without its model,
// so a measured model's data file may move or vanish.
TEST(MeasuredTable, ReadsAfterTheDataFileIsGone) {
  const std::string tab = temp_file("gone.tab"), merl = temp_file("gone.binary");
  exporting::write_tabulated(*parse_model("minnaert:xi=0.5"), {7, 7, 5}, tab);
  exporting::write_merl(*parse_model("lambert"), merl);
  for (const std::string& spec : {"tabulated:file=" + tab, "merl:file=" + merl}) {
    tables::BakeOptions options;
    options.resolution = {5};
    options.tolerance = 1e-4;  // measured data are no better than ~1e-4 (docs/measured.md)
    const tables::Table baked = tables::bake(*parse_model(spec), Law::h, options);
    const std::string exr = temp_file("gone.h.exr");
    tables::write_table(baked, exr);
    std::filesystem::remove(parse_spec(spec).terms[0].model.file);
    ASSERT_THROW(parse_model(spec), InputError);  // the model itself cannot be made any more
    const tables::Table read = tables::read_table(exr);
    EXPECT_EQ(read.model, baked.model);
    EXPECT_EQ(read.model_content, baked.model_content);
    EXPECT_TRUE(util::is_content_digest(read.model_content)) << read.model_content;
    EXPECT_EQ(read.value, baked.value);
    const Vec3 j{std::sqrt(0.75), 0.0, 0.5};
    EXPECT_EQ(tables::sample(read, Vec3{0, 0, 1}, j).value, tables::sample(baked, Vec3{0, 0, 1}, j).value);
  }
}

}  // namespace
}  // namespace ganzfeld
