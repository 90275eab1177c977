// Tables (tables/): bake -> write -> read -> sample against closed forms and the integrator, the
// storage encodings, and every refusal of the reader and the baker.
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include "tests/largest_allocation.h"
#include "tests/temp_dir.h"
#include "util/angles.h"
#include "util/atomic_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include "integrate/laws.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "tables/bspline.h"
#include "tables/cache.h"
#include "tables/exr_io.h"
#include "tables/frame.h"
#include "tables/sample.h"
#include "tables/table.h"
#include "tables/to_error.h"
#include "util/error.h"
#include "util/hash.h"

// Suite names start with lower-case "lut" so that `ctest -R lut` selects exactly these tests.
namespace ganzfeld {
using namespace ganzfeld::tables;

namespace {

namespace fs = std::filesystem;
using std::numbers::pi;

// --- Tolerances -----------------------------------------------------------------------------
// Cubature tolerance of the test bakes: the integrator's default (integrate/cubature.h).
constexpr double kBakeTol = 1e-9;
// Mapping round trip u -> x -> u: a few ulps of acos/sqrt near the ends, where d u/d x is
// largest (acos'(1 - 2t) ~ 1/sqrt(t) amplifies the rounding of t ~ 1e-16 to ~1e-8).
constexpr double kMappingRoundTrip = 1e-7;
// Linear interpolation error of a C^2 function F(u) on a grid of spacing du is at most
// max|F''| du^2 / 8 (standard bound). The bounds below instantiate it per law and mapping.
double interpolation_bound(double max_second_derivative, int count) {
  const double du = 1.0 / (count - 1);
  return max_second_derivative * du * du / 8.0;
}
// specular:alpha=8 g at 25x25x13 sampled between nodes: there is no closed form for the
// interpolation error, so this is measured: 5.6e-3 max over the 200 seeded points below (the test
// prints it), with a margin of ~1.6x. A regression in the mapping or the interpolation shows up as errors of the
// order of g itself (~0.1-1).
constexpr double kSpecularInterpolation = 9e-3;
// Sampling exactly at a node must return the node: only the index arithmetic intervenes
// (frac = s - floor(s) with s = u (count - 1) computed through the mapping's inverse).
constexpr double kAtNode = 1e-6;

constexpr std::uint64_t kSeed = 20240601;

using testing_support::temp_dir;
std::string temp_file(const std::string& name) { return (fs::path(temp_dir()) / name).string(); }

Table bake_table(const std::string& spec, Law law, std::vector<int> res, Encoding enc = Encoding::single) {
  BakeOptions options;
  options.resolution = std::move(res);
  options.tolerance = kBakeTol;
  options.encoding = enc;
  Table t = bake(*parse_model(spec), law, options);
  t.command = "lut_test";
  return t;
}

Table round_trip(const Table& table, const std::string& name) {
  const std::string path = temp_file(name);
  write_table(table, path);
  return read_table(path);
}

Vec3 from_cos(double c, double phi = 0.0) {
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  return {s * std::cos(phi), s * std::sin(phi), c};
}

// --- Axes and mappings ----------------------------------------------------------------------

TEST(Table, MappingsRoundTripAndEndsAreExact) {
  for (Mapping m : {Mapping::linear, Mapping::sqrt, Mapping::cos}) {
    const Axis axis{"x", -1.0, 1.0, 17, m};
    EXPECT_EQ(axis.node(0), -1.0) << to_string(m);
    EXPECT_EQ(axis.node(16), 1.0) << to_string(m);
    for (int k = 0; k <= 100; ++k) {
      const double u = k / 100.0;
      EXPECT_NEAR(axis.index_coordinate(axis.coordinate(u)), u, kMappingRoundTrip) << to_string(m) << " u=" << u;
    }
    // Clamping: outside the axis the index coordinate is the end's.
    EXPECT_EQ(axis.index_coordinate(-5.0), 0.0);
    EXPECT_EQ(axis.index_coordinate(5.0), 1.0);
  }
  // The documented formulas (docs/lut-format.md), at one point each.
  const Axis sq{"x", 0.0, 1.0, 5, Mapping::sqrt};
  EXPECT_DOUBLE_EQ(sq.node(1), 1.0 / 16.0);  // u = 1/4, x = u^2
  const Axis cs{"x", -1.0, 1.0, 5, Mapping::cos};
  EXPECT_DOUBLE_EQ(cs.node(1), -std::cos(pi / 4));  // on [-1, 1]: x = -cos(pi u), uniform in angle
}

// AxisIndex multiplies by 1 / (max - min) where that range is a power of two, instead of dividing:
// the identity x / 2^k = x 2^-k holds to the last bit, so a lookup (and with it a bake's validation
// and its warped nodes, tables/frame.h) is the same double as the quotient's. Elsewhere it divides.
TEST(Table, IndexCoordinateIsTheQuotientToTheLastBit) {
  std::mt19937_64 random(11);
  const Axis axes[] = {
      {"x", -1.0, 1.0, 9, Mapping::cos},   {"x", 0.0, 1.0, 9, Mapping::cos},     {"x", 0.0, 1.0, 9, Mapping::sqrt},
      {"x", 0.0, 1.0, 9, Mapping::linear}, {"x", -3.0, 5.0, 9, Mapping::linear}, {"x", 0.0, pi, 9, Mapping::linear},
      {"x", 0.0, pi / 2, 9, Mapping::cos}, {"x", 0.1, 0.85, 9, Mapping::sqrt},   {"x", -1.0, 2.0, 9, Mapping::linear}};
  for (const Axis& axis : axes) {
    std::uniform_real_distribution<double> inside(axis.min, axis.max);
    for (int k = 0; k < 20000; ++k) {
      const double x = inside(random);
      const double t = std::clamp((x - axis.min) / (axis.max - axis.min), 0.0, 1.0);  // the quotient itself
      const double u = axis.mapping == Mapping::linear ? t
                       : axis.mapping == Mapping::sqrt ? std::sqrt(t)
                                                       : util::acos_fast(1.0 - 2.0 * t) / pi;
      ASSERT_EQ(axis.index_coordinate(x), u)
          << to_string(axis.mapping) << " on [" << axis.min << ", " << axis.max << "] at x = " << x;
    }
  }
}

// The arctangent every lookup takes its angles from (util/angles.h: lobe and warped frames, the
// relative azimuth) against glibc's: a few ulps of the angle everywhere, IEEE's signs and special
// values, and monotone along a sweep (a warped frame's inverse bisects on it: tables/frame.cpp).
TEST(Table, LookupArctangentIsWithinAFewUlpsOfLibm) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), decades(-12.0, 12.0);
  for (int k = 0; k < 200000; ++k) {
    const double y = unit(random) * std::pow(10.0, decades(random)), x = unit(random) * std::pow(10.0, decades(random));
    const double exact = std::atan2(y, x);
    ASSERT_NEAR(util::atan2_fast(y, x), exact, 1e-15 * std::abs(exact) + 1e-300) << "atan2(" << y << ", " << x << ")";
    const double c = unit(random);
    ASSERT_NEAR(util::acos_fast(c), std::acos(c), 1e-15 * std::acos(c)) << "acos(" << c << ")";
  }
  const double inf = HUGE_VAL;
  for (const double y : {0.0, -0.0, 1.0, -1.0, inf, -inf})
    for (const double x : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
      const double want = std::atan2(y, x), got = util::atan2_fast(y, x);
      EXPECT_NEAR(got, want, 1e-15 * std::abs(want)) << "atan2(" << y << ", " << x << ")";
      EXPECT_EQ(std::signbit(got), std::signbit(want)) << "atan2(" << y << ", " << x << ")";
    }
  EXPECT_TRUE(std::isnan(util::atan2_fast(std::nan(""), 1.0)));
  EXPECT_TRUE(std::isnan(util::atan2_fast(1.0, std::nan(""))));
  EXPECT_TRUE(std::isnan(util::acos_fast(1.5)));
  double previous = -1.0;
  for (int k = 0; k <= 100000; ++k) {  // the angle of (sin, cos) of a sweep over [0, pi]
    const double a = pi * k / 100000.0, angle = util::atan2_fast(std::sin(a), std::cos(a));
    ASSERT_GE(angle, previous) << "at " << a;
    previous = angle;
  }
}

TEST(Table, ResolutionParsing) {
  EXPECT_EQ(parse_resolution("8", Law::g), (std::vector<int>{8, 8, 8}));
  EXPECT_EQ(parse_resolution("64x32x16", Law::g), (std::vector<int>{64, 32, 16}));
  EXPECT_EQ(parse_resolution("100", Law::h), (std::vector<int>{100}));
  for (const char* bad : {"0", "1", "8x8", "8x8x8x8", "x", "8x", "-8", "abc", "8.5", "9999999999"})
    EXPECT_THROW(parse_resolution(bad, Law::g), InputError) << bad;
  EXPECT_THROW(parse_resolution("8x8x8", Law::h), InputError);
}

// --- Bake, write, read, sample ----------------------------------------------------------------

// minnaert:xi=1: h = (j·n)^xi = j·n (K&P closed form). Axis cos_theta_j, sqrt mapping: F(u) =
// u^2, F'' = 2.
TEST(Table, MinnaertDarkeningRoundTrip) {
  constexpr int kCount = 50;  // not 2^k + 1: sqrt-mapped nodes k^2/49^2 are not exact in float
  const Table baked = bake_table("minnaert:xi=1", Law::h, {kCount});
  const Table table = round_trip(baked, "minnaert_h.exr");
  ASSERT_EQ(table.value, baked.value);  // bit-exact round trip
  ASSERT_EQ(table.error, baked.error);
  EXPECT_EQ(table.model, "minnaert:xi=1");
  EXPECT_EQ(table.command, "lut_test");
  EXPECT_EQ(table.unconverged, 0);
  // At the nodes the stored error bounds the true error (cubature + float rounding).
  for (int k = 0; k < kCount; ++k) {
    const double x = table.axes[0].node(k);
    EXPECT_LE(std::abs(table.value[k] - x), table.error[k]) << "node " << k;
  }
  const double bound = interpolation_bound(2.0, kCount);
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 200; ++n) {
    const double c = unit(rng);
    const Sample s = sample(table, Vec3{0, 0, 1}, from_cos(c));
    EXPECT_NEAR(s.value, c, bound + s.error) << "j·n=" << c;
  }
}

// lambert: g = (1 + i·n)/2 (K&P). Axis cos_theta_i uses the cos mapping x = -cos(pi u):
// F(u) = (1 - cos(pi u))/2, |F''| <= pi^2/2; g does not depend on the other axes.
TEST(Table, LambertVignettingRoundTrip) {
  constexpr int kCount = 33;
  const Table table = round_trip(bake_table("lambert", Law::g, {kCount, 5, 5}), "lambert_g.exr");
  const double bound = interpolation_bound(pi * pi / 2, kCount);
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> ci(-1.0, 1.0), cj(0.0, 1.0), phi(-pi, pi);
  for (int n = 0; n < 200; ++n) {
    const double c = ci(rng);
    const Sample s = sample(table, from_cos(c), from_cos(cj(rng), phi(rng)));
    EXPECT_NEAR(s.value, 0.5 * (1.0 + c), bound + s.error) << "i·n=" << c;
  }
  // At the nodes: exact up to the stored error.
  const Sample top = sample(table, Vec3{0, 0, 1}, Vec3{0, 0, 1});
  EXPECT_LE(std::abs(top.value - 1.0), top.error);
  const Sample bottom = sample(table, Vec3{0, 0, -1}, Vec3{0, 0, 1});
  EXPECT_LE(std::abs(bottom.value - 0.0), bottom.error);
}

// specular:alpha=8 g: nodes against the integrator directly, random points against it within
// the measured interpolation tolerance.
TEST(Table, SpecularVignettingAgreesWithIntegrator) {
  const Table table = round_trip(bake_table("specular:alpha=8", Law::g, {25, 25, 13}), "specular_g.exr");
  const ModelPtr model = parse_model("specular:alpha=8");
  CubatureOptions options;
  options.abs_tol = kBakeTol;
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> ci(-1.0, 1.0), cj(0.0, 1.0), phi(0.0, pi);
  std::uniform_int_distribution<int> k25(0, 24), k13(0, 12);
  for (int n = 0; n < 50; ++n) {  // at nodes
    const int a = k25(rng), b = k25(rng), c = k13(rng);
    const double x[3] = {table.axes[0].node(a), table.axes[1].node(b), table.axes[2].node(c)};
    const Estimate ref = vignetting(*model, from_cos(x[0]), from_cos(x[1], x[2]), options);
    const Sample s = sample(table, x);
    EXPECT_NEAR(s.value, ref.value, s.error + ref.error + kAtNode) << a << "," << b << "," << c;
  }
  double worst = 0.0;
  for (int n = 0; n < 200; ++n) {  // between nodes
    const Vec3 i = from_cos(ci(rng)), j = from_cos(cj(rng), phi(rng));
    const Estimate ref = vignetting(*model, i, j, options);
    const Sample s = sample(table, i, j);
    worst = std::max(worst, std::abs(s.value - ref.value));
    EXPECT_NEAR(s.value, ref.value, kSpecularInterpolation) << "i·n=" << i.z << " j·n=" << j.z;
  }
  std::printf("specular:alpha=8 g 25x25x13: max |table - integrator| between nodes = %.3g (tolerance %.3g)\n", worst,
              kSpecularInterpolation);
}

// The relative azimuth is folded into [0, pi] and is the same for both signs.
TEST(Table, RelativeAzimuthIsFoldedAndRotationInvariant) {
  const auto a = coordinates(Law::g, direction(0.7, 0.3), direction(0.4, 0.3 + 2.0));
  const auto b = coordinates(Law::g, direction(0.7, 1.3), direction(0.4, 1.3 - 2.0));
  EXPECT_NEAR(a[2], 2.0, 1e-12);
  EXPECT_NEAR(b[2], 2.0, 1e-12);
  const auto c = coordinates(Law::g, direction(0.7, 0.0), direction(0.4, 2 * pi - 0.5));
  EXPECT_NEAR(c[2], 0.5, 1e-12);
}

TEST(Table, HalfEncodingRoundsValuesAndBoundsTheirError) {
  // 30 nodes: with 2^k + 1 nodes the sqrt mapping puts every node on k^2/2^(2k), exact in half.
  const Table single = bake_table("minnaert:xi=1", Law::a, {30});
  const Table half = round_trip(bake_table("minnaert:xi=1", Law::a, {30}, Encoding::half), "minnaert_a_half.exr");
  EXPECT_EQ(half.encoding, Encoding::half);
  // Half keeps 11 significant bits: relative rounding 2^-11 of values in [0, 1].
  constexpr double kHalfRounding = 1.0 / 2048;
  bool any_different = false;
  for (std::size_t m = 0; m < half.value.size(); ++m) {
    const double exact = half.axes[0].node(static_cast<int>(m));  // a = i·n for minnaert:xi=1
    EXPECT_NEAR(half.value[m], single.value[m], kHalfRounding * std::abs(single.value[m]) + 1e-7);
    EXPECT_LE(std::abs(half.value[m] - exact), half.error[m]) << "entry " << m;
    any_different = any_different || half.value[m] != single.value[m];
  }
  EXPECT_TRUE(any_different) << "half encoding did not round anything";
  EXPECT_GT(half.node_error, single.node_error);
  EXPECT_LT(single.node_error, 1e-6);  // float: cubature + 2^-24 relative
}

// unorm16: value = offset + scale u / 65535; rounding to the nearest code errs by at most half a
// step, scale / 131070, plus the float rounding of the value (2^-24 relative; values <= 1 here).
constexpr double kUnormHalfStep = 1.0 / 131070;
constexpr double kFloatRounding = 1.0 / (1 << 24);
TEST(Table, Unorm16EncodingRoundTripsExactCodesAndBoundsItsRounding) {
  // h of specular:alpha=8 spans [0.21, 1]: an offset and a scale other than 0 and 1.
  const Table single = bake_table("specular:alpha=8", Law::h, {30});
  const Table baked = bake_table("specular:alpha=8", Law::h, {30}, Encoding::unorm16);
  const Table unorm = round_trip(baked, "specular_h_unorm16.exr");
  EXPECT_GT(unorm.unorm.offset, 0.0f);
  EXPECT_LT(unorm.unorm.scale, 1.0f);
  EXPECT_EQ(unorm.encoding, Encoding::unorm16);
  EXPECT_EQ(unorm.unorm.offset, baked.unorm.offset);
  EXPECT_EQ(unorm.unorm.scale, baked.unorm.scale);
  EXPECT_EQ(unorm.value, baked.value);  // bit for bit: the file holds the codes
  EXPECT_EQ(unorm.error, baked.error);
  EXPECT_EQ(value_bytes(unorm), 2 * unorm.entries());
  // The range spans the codes: the smallest node is code 0, the largest 65535.
  const auto [lo, hi] = std::minmax_element(single.value.begin(), single.value.end());
  EXPECT_LE(unorm.unorm.offset, *lo);
  EXPECT_GE(static_cast<double>(unorm.unorm.offset) + unorm.unorm.scale, *hi);
  EXPECT_EQ(unorm.unorm.code(*lo), 0);
  EXPECT_EQ(unorm.unorm.code(*hi), 65535);
  bool any_different = false;
  for (std::size_t m = 0; m < unorm.value.size(); ++m) {
    EXPECT_NEAR(unorm.value[m], single.value[m], unorm.unorm.scale * kUnormHalfStep + kFloatRounding) << "entry " << m;
    EXPECT_EQ(unorm.unorm.value(unorm.unorm.code(unorm.value[m])), unorm.value[m]) << "entry " << m;
    // The law is within single.error of the float value, so a bound of |unorm - law| must be at
    // least |unorm - single| - single.error: the rounding to the code is in the error channel.
    EXPECT_GE(unorm.error[m] + single.error[m], std::abs(unorm.value[m] - single.value[m])) << "entry " << m;
    any_different = any_different || unorm.value[m] != single.value[m];
  }
  EXPECT_TRUE(any_different) << "unorm16 encoding did not round anything";
}

TEST(Table, Unorm16ValueOffTheCodesIsRefused) {
  Table table = bake_table("minnaert:xi=1", Law::a, {30}, Encoding::unorm16);
  table.value[5] = std::nextafter(table.value[5], 2.0f);  // between two codes' values
  EXPECT_THROW(check_table(table), InputError);
  EXPECT_THROW(write_table(table, temp_file("unorm16_off_codes.exr")), InputError);
  EXPECT_FALSE(fs::exists(temp_file("unorm16_off_codes.exr")));
}

TEST(Table, BakeIsDeterministicAcrossThreadCounts) {
  const Table parallel = bake_table("specular:alpha=8", Law::g, {9, 9, 5});
  Table serial;
  tbb::task_arena one(1);
  one.execute([&] { serial = bake_table("specular:alpha=8", Law::g, {9, 9, 5}); });
  EXPECT_EQ(parallel.value, serial.value);
  EXPECT_EQ(parallel.error, serial.error);
}

TEST(Table, UnconvergedEntriesAreCounted) {
  BakeOptions options;
  options.resolution = {5};
  options.tolerance = 1e-15;       // beyond double precision for these integrals ...
  options.max_evaluations = 1000;  // ... and a budget far too small to try
  const Table t = bake(*parse_model("specular:alpha=1000"), Law::h, options);
  EXPECT_GT(t.unconverged, 0);
  EXPECT_GT(t.node_error, options.tolerance);
}

TEST(Table, ACancelledBakeThrowsAndWritesNothing) {
  std::atomic<bool> cancel{true};
  BakeOptions options;
  options.resolution = {9, 9, 5};
  options.cancel = &cancel;
  const ModelPtr m = parse_model("specular:alpha=8");
  EXPECT_THROW(bake(*m, Law::g, options), Cancelled);
  TargetBake target;  // the --max-error search stops at its first bake
  target.target.lookup_error = 1e-3;
  target.cancel = &cancel;
  EXPECT_THROW(bake(*m, Law::g, target), Cancelled);

  // Set while the nodes are baked (the progress callback runs on the bake's workers).
  options.resolution = {33, 33, 17};
  cancel = false;
  std::atomic<std::uint64_t> seen{0};
  options.progress = [&](std::uint64_t done, std::uint64_t) {
    seen = done;
    cancel = true;
  };
  const std::string path = temp_file("cancelled.exr");
  EXPECT_THROW(bake_or_reuse(path, *m, Law::g, options, "lut_test"), Cancelled);
  EXPECT_LT(seen.load(), 33u * 33u * 17u) << "the bake ran to its end";
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(temp_dir()))
    EXPECT_EQ(entry.path().filename().string().find("cancelled.exr"), std::string::npos) << entry.path();
}

// --- Refusals --------------------------------------------------------------------------------

TEST(Table, BakeRefusesBadSizesBeforeAllocating) {
  const ModelPtr model = parse_model("lambert");
  BakeOptions options;
  options.resolution = {0};
  EXPECT_THROW(bake(*model, Law::h, options), InputError);
  options.resolution = {1};
  EXPECT_THROW(bake(*model, Law::h, options), InputError);
  options.resolution = {100000, 100000, 100000};  // 8e15 bytes: would throw bad_alloc if tried
  try {
    bake(*model, Law::g, options);
    FAIL() << "absurd resolution accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("8000000000000000 bytes"), std::string::npos) << e.what();
  }
  options.resolution = {8, 8};  // wrong number of axes for g
  EXPECT_THROW(bake(*model, Law::g, options), InputError);
  options.resolution = {8};
  EXPECT_THROW(bake(*model, Law::r, options), InputError);
}

/// An EXR's pixels and header, to write variants of a valid table that the reader must refuse.
struct RawExr {
  int width = 0, height = 0;
  Imf::Header header;
  std::map<std::string, std::vector<float>> channels;
  /// Attributes save() leaves out. Not Imf::Header::erase: OpenEXR 3.1's erase drops the
  /// attribute from its map without deleting it (LeakSanitizer reports it under --sanitize).
  std::set<std::string> dropped;

  static RawExr load(const std::string& path) {
    Imf::InputFile in(path.c_str());
    RawExr raw;
    raw.header = in.header();
    const auto window = raw.header.dataWindow();
    raw.width = window.max.x + 1;
    raw.height = window.max.y + 1;
    Imf::FrameBuffer frame;
    for (const char* name : {"value", "error"}) {
      auto& data = raw.channels[name];
      data.resize(static_cast<std::size_t>(raw.width) * raw.height);
      frame.insert(
          name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data()), sizeof(float), sizeof(float) * raw.width));
    }
    in.setFrameBuffer(frame);
    in.readPixels(0, raw.height - 1);
    return raw;
  }

  void save(const std::string& path) {
    Imf::Header h(width, height);
    for (auto it = header.begin(); it != header.end(); ++it)
      if (std::string(it.name()).rfind("ganzfeld.", 0) == 0 && !dropped.contains(it.name()))
        h.insert(it.name(), it.attribute());
    Imf::FrameBuffer frame;
    for (auto& [name, data] : channels) {
      h.channels().insert(name, Imf::Channel(Imf::FLOAT));
      frame.insert(name,
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data()), sizeof(float), sizeof(float) * width));
    }
    Imf::OutputFile out(path.c_str(), h);
    out.setFrameBuffer(frame);
    out.writePixels(height);
  }

  void set(const char* name, const std::string& value) { header.insert(name, Imf::StringAttribute(value)); }
};

class TableRefusal : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    valid_ = new std::string(temp_file("valid_h.exr"));
    write_table(bake_table("minnaert:xi=1", Law::h, {9}), *valid_);
  }
  static void TearDownTestSuite() { delete valid_; }

  /// read_table(path) must throw an InputError whose one-line message names the file and
  /// contains `reason`.
  static void expect_refused(const std::string& path, const std::string& reason) {
    try {
      read_table(path);
      ADD_FAILURE() << path << " was accepted; expected a refusal mentioning '" << reason << "'";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(reason), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }

  static RawExr valid() { return RawExr::load(*valid_); }
  /// `raw` saved as `file`; its path.
  static std::string saved(RawExr raw, const std::string& file) {
    const std::string path = temp_file(file);
    raw.save(path);
    return path;
  }
  /// The valid table with attribute `name` set to `value`, saved as `file`; its path.
  static std::string valid_with(const char* name, const std::string& value, const std::string& file) {
    RawExr raw = valid();
    raw.set(name, value);
    return saved(raw, file);
  }
  static std::string* valid_;
};
std::string* TableRefusal::valid_ = nullptr;

TEST_F(TableRefusal, ValidFileIsAccepted) { EXPECT_NO_THROW(read_table(*valid_)); }

TEST_F(TableRefusal, MissingFile) { expect_refused(temp_file("does_not_exist.exr"), "no such file"); }

TEST_F(TableRefusal, NotExr) {
  const std::string path = temp_file("text.exr");
  std::ofstream(path) << "this is not an image\n";
  expect_refused(path, "not an OpenEXR file");
}

TEST_F(TableRefusal, Truncated) {
  const std::string path = temp_file("truncated.exr");
  std::ifstream in(*valid_, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t keep : {bytes.size() - 8, bytes.size() / 2, std::size_t{600}}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, keep);
    expect_refused(path, "truncated");
  }
}

// Each edit of a valid table's header or pixels, and the refusal it must draw.
TEST_F(TableRefusal, BrokenHeadersAndPixels) {
  const std::vector<std::tuple<const char*, std::function<void(RawExr&)>, const char*>> cases{
      {"no_version.exr", [](RawExr& raw) { raw.dropped.insert("ganzfeld.format_version"); },
       "missing string attribute ganzfeld.format_version"},
      {"version3.exr", [](RawExr& raw) { raw.set("ganzfeld.format_version", "3"); },
       "format version '3' is not supported"},
      {"wrong_shape.exr",  // 9 x 1 image for a 9-node axis
       [](RawExr& raw) {
         raw.width = 8;
         for (auto& [name, data] : raw.channels) data.resize(8);
       },
       "image is 8x1 but the axes need 9x1"},
      {"one_channel.exr", [](RawExr& raw) { raw.channels.erase("error"); }, "expected exactly {error, value}"},
      {"g_one_axis.exr", [](RawExr& raw) { raw.set("ganzfeld.law", "g"); },  // g needs 3 axes, the file has 1
       "law g needs 3 axes"},
      {"nan.exr", [](RawExr& raw) { raw.channels["value"][3] = std::nanf(""); }, "every value must be finite"},
      {"max_error.exr", [](RawExr& raw) { raw.set("ganzfeld.max_error", "0"); }, "disagrees with the error data"},
  };
  for (const auto& [file, edit, reason] : cases) {
    RawExr raw = valid();
    edit(raw);
    expect_refused(saved(raw, file), reason);
  }
}

// The model spec is kept as text: a model this build does not know (or whose data file is gone,
// tests/measured_test.cpp) still reads; only a spec no header line should hold is refused.
TEST_F(TableRefusal, ModelSpecIsNotParsed) {
  EXPECT_EQ(read_table(valid_with("ganzfeld.model", "future-model:x=1", "future_model.exr")).model, "future-model:x=1");
}

TEST_F(TableRefusal, ModelSpecBlankOrMultiLine) {
  for (const char* spec : {"", " ", "minnaert:xi=1\nlambert"})
    expect_refused(valid_with("ganzfeld.model", spec, "bad_model.exr"),
                   "expected one non-empty line of printable text");
}

// ganzfeld.model_content: optional, so tables written before it existed still read.
TEST_F(TableRefusal, ModelContentMissingReadsAsNone) {
  RawExr raw = valid();
  raw.dropped.insert("ganzfeld.model_content");
  const std::string path = temp_file("no_content.exr");
  raw.save(path);
  EXPECT_EQ(read_table(path).model_content, "");
  const std::string digest = "fnv1a64:0123456789abcdef";
  EXPECT_EQ(read_table(valid_with("ganzfeld.model_content", digest, "content.exr")).model_content, digest);
}

// ganzfeld.values_digest: one number changed under the metadata (here by the least step a
// float takes, which no other check sees: the error channel and its maximum are untouched).
TEST_F(TableRefusal, ANumberChangedUnderItsDigest) {
  RawExr raw = valid();
  float& v = raw.channels["value"][3];
  v = std::nextafter(v, 2.0f * v + 1.0f);
  const std::string path = temp_file("one_float.exr");
  raw.save(path);
  expect_refused(path, "the numbers do not match ganzfeld.values_digest");
  RawExr error_changed = valid();
  std::vector<float>& error = error_changed.channels["error"];
  const auto [smallest, largest] = std::minmax_element(error.begin(), error.end());
  ASSERT_LT(*smallest, *largest);
  *smallest = 0.5f * (*smallest + *largest);  // below the maximum: ganzfeld.max_error still holds
  error_changed.save(path);
  expect_refused(path, "the numbers do not match ganzfeld.values_digest");
}

TEST_F(TableRefusal, ValuesDigestMissingReadsAsNone) {
  const Table written = read_table(*valid_);
  EXPECT_EQ(written.values_digest, values_digest(written));
  EXPECT_TRUE(util::is_content_digest(written.values_digest)) << written.values_digest;
  RawExr raw = valid();
  raw.dropped.insert("ganzfeld.values_digest");
  const std::string path = temp_file("no_values_digest.exr");
  raw.save(path);
  const Table old = read_table(path);
  EXPECT_EQ(old.values_digest, "");
  EXPECT_EQ(old.value, written.value);
}

// The cache reuses only verified numbers: a changed number, or no digest to check them by (a
// file written before it existed), is re-baked, and read_if_matching says why.
TEST(Table, CacheRebakesNumbersItCannotVerify) {
  const ModelPtr m = parse_model("minnaert:xi=1");
  BakeOptions options;
  options.resolution = {9};
  const TableKey key = table_key(*m, Law::h, options);
  const std::string path = (fs::path(temp_dir()) / cache_file_name(key)).string();
  const CacheResult first = bake_or_reuse(path, *m, Law::h, options, "lut_test");
  std::string why = "unset";
  EXPECT_TRUE(read_if_matching(path, key, &why));
  EXPECT_EQ(why, "");
  for (const bool drop_digest : {false, true}) {
    RawExr raw = RawExr::load(path);
    if (drop_digest) raw.dropped.insert("ganzfeld.values_digest");
    else raw.channels["value"][4] *= 1.0f + 1e-6f;
    raw.save(path);
    EXPECT_FALSE(read_if_matching(path, key, &why));
    EXPECT_NE(why.find(drop_digest ? "no ganzfeld.values_digest" : "do not match ganzfeld.values_digest"),
              std::string::npos)
        << why;
    const CacheResult again = bake_or_reuse(path, *m, Law::h, options, "lut_test");
    EXPECT_EQ(again.status, CacheStatus::baked);
    EXPECT_EQ(read_table(path).value, first.table.value);
    EXPECT_EQ(bake_or_reuse(path, *m, Law::h, options, "lut_test").status, CacheStatus::reused);
  }
}

TEST_F(TableRefusal, ModelContentMalformed) {
  for (const char* digest : {"0123456789abcdef", "fnv1a64:0123", "sha256:0123456789abcdef"})
    expect_refused(valid_with("ganzfeld.model_content", digest, "bad_content.exr"),
                   std::string("model content '") + digest + "' is not allowed");
}

// A table whose header declares more than its bytes hold (a memory bomb: an 852-byte file whose
// attribute size of 1.6 GB OpenEXR 3.1 allocates before any check) is refused by
// tables/exr_guard.cpp before OpenEXR reads it: one line naming the attribute, no allocation
// beyond a small multiple of the file, quickly.
TEST_F(TableRefusal, ForgedSizesAreRefusedBeforeAllocating) {
  // OpenEXR allocates the header's strings and the pixel buffers; the valid 9-node table allocates
  // well under this. The forged sizes below are ~10^6 times the file.
  constexpr std::size_t kMaxAllocationPerFileByte = 64;
  // Refused from the header alone: far below the time of allocating and touching 1.6 GB.
  constexpr double kMaxSeconds = 0.5;
  std::ifstream in(*valid_, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto forge = [&](const std::string& attribute, std::size_t value_offset, std::int32_t value) {
    std::string forged = bytes;
    const auto at = forged.find(attribute + '\0');
    EXPECT_NE(at, std::string::npos) << attribute;
    const auto size_at = forged.find('\0', at + attribute.size() + 1) + 1;  // after the type name
    for (int k = 0; k < 4; ++k) forged[size_at + value_offset + k] = static_cast<char>((value >> (8 * k)) & 0xff);
    return forged;
  };
  const std::size_t kSizeField = 0, kValue = 4, kBoxMaxY = 4 + 12;
  for (const auto& [attribute, offset, value, reason] :
       {std::tuple{"ganzfeld.command", kSizeField, 1'600'000'000, "attribute 'ganzfeld.command' declares 1600000000"},
        std::tuple{"ganzfeld.axes", kSizeField, -5, "attribute 'ganzfeld.axes' declares a negative size"},
        std::tuple{"dataWindow", kBoxMaxY, 2'000'000'000, "scanlines needs"},
        std::tuple{"dataWindow", kValue + 8, 1'000'000, "more than 1100 times"},
        // Found by fuzz/table_fuzz.cpp (fuzz/corpus/table/oom-chlist-shorter-than-its-list): OpenEXR
        // reads a channel list to its terminator, past a declared size 1 byte short, and then
        // read the next attribute's bytes as a size of 1.6 GB. 45 = 2 × (6 + 16) + 1.
        std::tuple{"channels", kSizeField, 44, "does not end where its declared size says"},
        std::tuple{"compression", kSizeField, 4, "of type 'compression' declares 4 bytes; it has 1"}}) {
    const std::string path = temp_file("forged.exr");
    std::ofstream(path, std::ios::binary | std::ios::trunc) << forge(attribute, offset, value);
    const auto start = std::chrono::steady_clock::now();
    const std::size_t largest =
        testing_support::largest_allocation_during([&path, reason = reason] { expect_refused(path, reason); });
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), kMaxSeconds);
    EXPECT_LT(largest, kMaxAllocationPerFileByte * bytes.size()) << attribute;
  }
}

// --- Atomic writes ----------------------------------------------------------------------------

std::vector<std::string> listing(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(Table, FailedWriteLeavesNoFile) {
  const Table table = bake_table("lambert", Law::h, {5});
  // A directory that does not exist.
  const std::string missing = temp_file("no/such/dir/t.exr");
  EXPECT_THROW(write_table(table, missing), InputError);
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_THROW(check_writable(missing), InputError);

  // The rename fails after the temporary file was written (target is a non-empty directory):
  // the temporary must be gone and nothing else created.
  const fs::path dir = fs::path(temp_dir()) / "atomic";
  fs::create_directories(dir / "target.exr" / "occupied");
  const auto before = listing(dir.string());
  EXPECT_THROW(write_table(table, (dir / "target.exr").string()), InputError);
  EXPECT_EQ(listing(dir.string()), before);
  EXPECT_TRUE(fs::is_directory(dir / "target.exr"));

  // A read-only directory (only meaningful when not root: root ignores permission bits).
  if (::geteuid() != 0) {
    const fs::path ro = fs::path(temp_dir()) / "readonly";
    fs::create_directories(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(write_table(table, (ro / "t.exr").string()), InputError);
    EXPECT_TRUE(fs::is_empty(ro));
    fs::permissions(ro, fs::perms::owner_all);
  }

  // Success replaces an existing file atomically and leaves no temporary behind.
  const fs::path ok = dir / "ok.exr";
  write_table(table, ok.string());
  write_table(table, ok.string());
  EXPECT_NO_THROW(read_table(ok.string()));
  auto after = listing(dir.string());
  EXPECT_EQ(after.size(), before.size() + 1) << "a temporary file was left behind";
}

// The error a lookup reports (interpolated node errors + the table's measured interpolation
// error) must cover |lookup - cubature| between nodes, where interpolation dominates. The
// interpolation error is measured at cell centres, not bounded, so we allow a small fraction
// of misses at fresh random points.
constexpr double kAllowedMissFraction = 0.01;  // measured, not a bound: see tables/table.h
TEST(Table, ReportedErrorCoversInterpolationBetweenNodes) {
  struct Case {
    const char* spec;
    Law law;
    std::vector<int> res;
  };
  for (const Case& c : {Case{"specular:alpha=8", Law::g, {12, 12, 7}}, Case{"minnaert:xi=0.3", Law::h, {17}},
                        Case{"asperity:alpha=4", Law::a, {9}}}) {
    const ModelPtr model = parse_model(c.spec);
    BakeOptions options;
    options.resolution = c.res;
    options.tolerance = 1e-9;
    const Table baked = bake(*model, c.law, options);
    const Table table = round_trip(baked, "interpolation.exr");
    EXPECT_EQ(table.interpolation_error, baked.interpolation_error) << c.spec;  // survives the file
    EXPECT_EQ(table.interpolation_checks, baked.interpolation_checks) << c.spec;
    ASSERT_GT(table.interpolation_checks, 0) << c.spec;
    ASSERT_GT(table.interpolation_error, table.node_error) << c.spec;  // interpolation dominates here
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    CubatureOptions exact;
    exact.abs_tol = 1e-11;
    int misses = 0;
    constexpr int kPoints = 300;
    for (int k = 0; k < kPoints; ++k) {
      const Vec3 i = direction_from_cos(c.law == Law::g ? 2 * u(rng) - 1 : u(rng));
      const Vec3 j = direction_from_cos(u(rng), std::numbers::pi * u(rng));
      const Sample s = sample(table, i, j);
      const double truth = evaluate_law(*model, c.law, i, j, exact).value;
      if (std::abs(s.value - truth) > s.error + table.interpolation_error) ++misses;
    }
    EXPECT_LE(misses, kAllowedMissFraction * kPoints) << c.spec;
  }
}

// --- Format version 2: the lobe frame, Catmull–Rom, baking to a lookup error -----------------

// Lobe coordinates -> directions -> (i·n, j·n, phi) -> lobe coordinates: atan2 of well-scaled
// dot products, a few ulps of pi (psi and beta are angles up to pi).
constexpr double kLobeRoundTrip = 1e-12;
TEST(Table, LobeCoordinatesInvertLobeDirections) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (PeakKind peak : {PeakKind::mirror, PeakKind::retro}) {
    for (int k = 0; k < 500; ++k) {
      // Away from the coordinate poles (psi = 0, pi: beta undefined; theta_j = 0: phi undefined).
      const double y[3] = {0.01 + 1.5 * u(rng), 0.01 + 3.1 * u(rng), pi * u(rng)};
      const auto [i, j] = lobe_directions(peak, y[0], y[1], y[2]);
      const std::vector<double> x = coordinates(Law::g, i, j);
      const std::array<double, 3> back = lobe_coordinates(peak, x[0], x[1], x[2]);
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(back[d], y[d], kLobeRoundTrip) << to_string(peak) << " axis " << d;
    }
    // psi = 0 is the peak: the mirror direction of j (specular) or j itself (backscatter).
    const auto [i, j] = lobe_directions(peak, 0.7, 0.0, 1.0);
    const Vec3 want = peak == PeakKind::mirror ? mirror(j) : j;
    EXPECT_NEAR(glm::dot(i, want), 1.0, kLobeRoundTrip) << to_string(peak);
  }
}

TEST(Table, LobeFrameFollowsTheMassHints) {
  const auto specular = lobe_frame_of(*parse_model("specular:alpha=100"));
  ASSERT_TRUE(specular);
  EXPECT_EQ(specular->peak, PeakKind::mirror);
  EXPECT_DOUBLE_EQ(specular->width, std::sqrt(2.0 / 100.0));  // models/specular.cpp's hint
  const auto backscatter = lobe_frame_of(*parse_model("backscatter:alpha=100"));
  ASSERT_TRUE(backscatter);
  EXPECT_EQ(backscatter->peak, PeakKind::retro);
  EXPECT_FALSE(lobe_frame_of(*parse_model("lambert")));
  EXPECT_FALSE(lobe_frame_of(*parse_model("asperity:alpha=4")));
}

TEST(Table, SinhMappingsRoundTrip) {
  for (Mapping m : {Mapping::sinh, Mapping::sinh_max}) {
    Axis axis{"psi", 0.0, pi, 33, m, 0.0447};
    EXPECT_EQ(axis.node(0), 0.0);
    EXPECT_EQ(axis.node(32), pi);
    for (int k = 0; k <= 100; ++k) {
      const double uu = k / 100.0;
      EXPECT_NEAR(axis.index_coordinate(axis.coordinate(uu)), uu, kMappingRoundTrip) << to_string(m);
    }
  }
  // sinh is dense at the centre, sinh_max at max: the first cells on those sides are the narrowest.
  const Axis centred{"psi", 0.0, pi, 33, Mapping::sinh, 0.0447};
  EXPECT_LT(centred.node(17) - centred.node(16), centred.node(1) - centred.node(0) / 10);
  const Axis towards_max{"theta_j", 0.0, pi / 2, 33, Mapping::sinh_max, 0.27};
  EXPECT_LT(towards_max.node(32) - towards_max.node(31), towards_max.node(1) - towards_max.node(0));
}

// Catmull–Rom with the quadratic-extrapolation ends reproduces quadratics in the index
// coordinate everywhere, boundary cells included (it is exact for degree <= 2); with the even
// ends (azimuths) it reproduces functions even about both ends, e.g. cos(pi s / (n - 1)) to
// its interpolation error. Only float storage of the node values rounds.
TEST(Table, CatmullRomReproducesPolynomials) {
  Table t;
  t.law = Law::h;
  t.model = "lambert";
  t.interpolation = Interpolation::catmull_rom;
  t.axes = {{kAxisCosThetaJ, 0.0, 1.0, 9, Mapping::linear}};
  auto fill = [&](auto f) {
    t.value.resize(9);
    t.error.assign(9, 0.0f);
    for (int k = 0; k < 9; ++k) t.value[k] = static_cast<float>(f(static_cast<double>(k)));
  };
  const auto quadratic = [](double s) { return 0.5 + 0.25 * s - 0.125 * s * s; };  // exact in float at nodes
  fill(quadratic);
  for (int k = 0; k <= 800; ++k) {
    const double x = k / 800.0;
    const double want = quadratic(8 * x);
    EXPECT_NEAR(sample_axes(t, std::span<const double>(&x, 1)).value, want, 1e-12) << "x=" << x;
  }
  // Even ends: an axis named phi reflects. A function even about both ends, cos(pi s / 4) on 9
  // nodes: Catmull–Rom with reflected ghost nodes errs by at most 8.93e-3 (the same weights
  // evaluated independently in double precision on 8001 points); with quadratic extrapolation
  // at the ends instead it would err by 1.87e-2.
  t.axes = {{kAxisPhi, 0.0, pi, 9, Mapping::linear}};
  const auto even = [](double s) { return std::cos(pi * s / 4); };
  fill(even);
  constexpr double kCatmullRomCosError = 9.0e-3;
  for (int k = 0; k <= 800; ++k) {
    const double x = pi * k / 800.0;
    EXPECT_NEAR(sample_axes(t, std::span<const double>(&x, 1)).value, std::cos(2.0 * x), kCatmullRomCosError)
        << "x=" << x;
  }
}

// The 8-bit lookups at y (weights rounded to nearest, truncated) within `reach` / 512 and / 256 of
// the exact one (`reach`: the summed largest steps between the blended entries along each axis;
// `slack`: float rounding). Returns whether the nearest-rounded lookup moved at all.
using LookupFunction = Sample (*)(const Table&, std::span<const double>, WeightRounding) noexcept;
bool expect_8bit_lookups_within(const Table& t, std::span<const double> y, double reach, double slack,
                                LookupFunction lookup) {
  const double exact = lookup(t, y, WeightRounding::exact).value;
  const double nearest = lookup(t, y, WeightRounding::nearest).value;
  const double truncated = lookup(t, y, WeightRounding::truncate).value;
  EXPECT_LE(std::abs(nearest - exact), reach / 512 + slack);
  EXPECT_LE(std::abs(truncated - exact), reach / 256 + slack);
  return nearest != exact;
}

// The b-spline lookup (tables/bspline.h) checked against an independent evaluation: the spline
// S(s) = sum_k c_k B(s - k), s = 1 + u (count - 3), summed in double over every stored coefficient
// with the cubic B-spline B written out piecewise. The solve makes S pass through the law at the
// count - 2 nodes; both end conditions reproduce cubics (an even one: cubics even about the ends)
// everywhere, ends included; the error falls as h^4 up to the ends (16x per halving: >= 12x asserted);
// the stored error bounds how far the spline moves when the node values move within their errors.
double cubic_bspline(double x) {
  const double a = std::abs(x);
  if (a >= 2.0) return 0.0;
  if (a >= 1.0) return (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
  return (4.0 - 6.0 * a * a + 3.0 * a * a * a) / 6.0;
}
double spline_by_definition(const Table& t, double u) {
  const int n = t.axes[0].count;
  const double s = 1.0 + u * (n - 3);
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += t.value[k] * cubic_bspline(s - k);
  return sum;
}
Table bspline_line(const char* axis_name, double max, int count, const std::function<double(double)>& f,
                   double node_error = 0.0) {
  Table t;
  t.law = Law::h;
  t.model = "lambert";
  t.interpolation = Interpolation::bspline;
  t.axes = {{axis_name, 0.0, max, count, Mapping::linear}};
  std::vector<double> value;
  for (double x : bspline_nodes(t.axes[0])) value.push_back(f(x));
  const Coefficients c = bspline_coefficients(t.axes, value, std::vector<double>(value.size(), node_error));
  t.value.assign(c.value.begin(), c.value.end());
  t.error.assign(c.error.begin(), c.error.end());
  return t;
}
double largest_error(const Table& t, const std::function<double(double)>& f) {
  double worst = 0.0;
  for (int p = 0; p <= 2000; ++p) {
    const double x = t.axes[0].max * p / 2000.0;
    worst = std::max(worst, std::abs(sample_axes(t, std::span<const double>(&x, 1)).value - f(x)));
  }
  return worst;
}
TEST(Table, BSplineIsTheSplineThroughTheNodes) {
  const auto smooth = [](double x) { return std::exp(-x) * std::sin(3.0 * x) + 0.3; };
  const Table t = bspline_line(kAxisCosThetaJ, 1.0, 11, smooth);
  ASSERT_EQ(bspline_nodes(t.axes[0]).size(), 9u);
  for (int p = 0; p <= 1000; ++p) {
    const double x = p / 1000.0;
    EXPECT_NEAR(sample_axes(t, std::span<const double>(&x, 1)).value, spline_by_definition(t, x), 1e-12) << x;
  }
  for (double x : bspline_nodes(t.axes[0]))
    EXPECT_NEAR(sample_axes(t, std::span<const double>(&x, 1)).value, smooth(x), 1e-6) << "node " << x;
  const auto cubic = [](double x) { return 0.25 + 0.5 * x - 0.75 * x * x + 0.4 * x * x * x; };
  EXPECT_LT(largest_error(bspline_line(kAxisCosThetaJ, 1.0, 7, cubic), cubic), 1e-6);
  const auto even_cubic = [](double x) { return 1.0 - 3.0 * x * x + 2.0 * x * x * x / pi; };  // S' = 0 at 0, pi
  EXPECT_LT(largest_error(bspline_line(kAxisPhi, pi, 7, even_cubic), even_cubic), 1e-6);
  const double coarse = largest_error(bspline_line(kAxisCosThetaJ, 1.0, 11, smooth), smooth);
  const double fine = largest_error(bspline_line(kAxisCosThetaJ, 1.0, 19, smooth), smooth);
  std::printf("b-spline: %.3g (9 nodes), %.3g (17 nodes), ratio %.1f\n", coarse, fine, coarse / fine);
  EXPECT_GT(coarse / fine, 12.0);
  const auto cosine = [](double x) { return std::cos(2.0 * x); };  // even about 0 and pi
  const double even_coarse = largest_error(bspline_line(kAxisPhi, pi, 11, cosine), cosine);
  const double even_fine = largest_error(bspline_line(kAxisPhi, pi, 19, cosine), cosine);
  std::printf("b-spline even axis: %.3g, %.3g, ratio %.1f\n", even_coarse, even_fine, even_coarse / even_fine);
  EXPECT_GT(even_coarse / even_fine, 12.0);
  // Node values moved by up to 1e-3 each (seeded signs and sizes): the spline moves by no more
  // than the stored bound, which is the Lebesgue constant (between 1 and 2 here) times 1e-3.
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> shift(-1e-3, 1e-3);
  for (const char* name : {kAxisCosThetaJ, kAxisPhi}) {
    const Table exact = bspline_line(name, 1.0, 12, smooth, 1e-3);
    EXPECT_GT(exact.error[0], 1e-3);
    EXPECT_LT(exact.error[0], 2e-3);
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<double> moved;
      for (double x : bspline_nodes(exact.axes[0])) {  // trial 0: all up; 1: alternating (the worst case inside)
        const double by = trial == 0 ? 1e-3 : trial == 1 ? (moved.size() % 2 ? -1e-3 : 1e-3) : shift(rng);
        moved.push_back(smooth(x) + by);
      }
      const Coefficients c = bspline_coefficients(exact.axes, moved, std::vector<double>(moved.size(), 0.0));
      for (int p = 0; p <= 200; ++p) {
        double spline = 0.0;
        const double s = 1.0 + p / 200.0 * 9.0;
        for (int k = 0; k < 12; ++k) spline += c.value[k] * cubic_bspline(s - k);
        ASSERT_LE(std::abs(spline - spline_by_definition(exact, p / 200.0)), exact.error[0] + 1e-12) << name;
      }
    }
  }
}

// A warped table's lookup is A(theta_j) times the spline of g / A: the nodes' errors in g / A grow
// as A falls, but the lookup's error stays near the Lebesgue constant times their largest error in
// g. With a scale falling from 1 to 0.02, node values moved within their errors (all up,
// alternating, seeded) move the scaled spline at every point by no more than the error the lookup
// reports there (the coefficients' errors blended by its weights, times the scale), and each
// coefficient's error times the scale at its node is one bound, under a tenth of the unscaled one.
TEST(Table, BSplineBoundOfAScaledLookup) {
  const auto scale = [](double x) { return 0.02 + 0.98 * (1.0 - x) * (1.0 - x); };
  const auto smooth = [](double x) { return std::exp(-x) * std::sin(3.0 * x) + 0.3; };
  const std::vector<Axis> axes = {{kAxisCosThetaJ, 0.0, 1.0, 12, Mapping::linear}};
  const std::vector<double> nodes = bspline_nodes(axes[0]);
  std::vector<double> value, error;
  for (double x : nodes) {
    value.push_back(smooth(x) / scale(x));
    error.push_back(1e-3 / scale(x));
  }
  const Coefficients scaled = bspline_coefficients(axes, value, error, scale);
  const Coefficients unscaled = bspline_coefficients(axes, value, error);
  auto blend = [](const std::vector<double>& c, double x) {
    double sum = 0.0;
    for (int k = 0; k < 12; ++k) sum += c[k] * cubic_bspline(1.0 + 9.0 * x - k);
    return sum;
  };
  const double bound = scaled.error[0] * scale(nodes[0]);  // coefficient k is charged to node clamp(k, 1, 10) - 1
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(scaled.error[k] * scale(nodes[std::clamp(k, 1, 10) - 1]), bound, 1e-15);
  std::printf("scaled bound %.3g, unscaled %.3g\n", bound, unscaled.error[0]);
  EXPECT_GT(bound, 1e-3);
  EXPECT_LT(bound, 0.1 * unscaled.error[0]);
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> moved;
    for (std::size_t m = 0; m < nodes.size(); ++m)
      moved.push_back(value[m] + error[m] * (trial == 0 ? 1.0 : trial == 1 ? (m % 2 ? -1.0 : 1.0) : unit(rng)));
    const Coefficients c = bspline_coefficients(axes, moved, std::vector<double>(moved.size(), 0.0));
    for (int p = 0; p <= 400; ++p) {
      const double x = p / 400.0;
      const double reported = scale(x) * blend(scaled.error, x);
      ASSERT_LE(scale(x) * std::abs(blend(c.value, x) - blend(scaled.value, x)), reported + 1e-12) << trial << " " << x;
    }
  }
}

// The b-spline's hardware lookup: two linear fetches per axis whose fractions a GPU rounds to 8
// bits. A 3-D table of random coefficients: exact weights agree with the spline by definition (the
// tensor product of the 1-D sums), and the 8-bit lookups differ from it by at most the
// coefficients' largest step along each axis / 256 (truncated) or / 512 (nearest), summed.
TEST(Table, BSplineHardwareLookupRoundsOnlyTheFetchFractions) {
  Table t;
  t.law = Law::g;
  t.model = "lambert";
  t.interpolation = Interpolation::bspline;
  t.filter = Filter::hardware;
  t.axes = {{kAxisCosThetaI, -1.0, 1.0, 7, Mapping::linear},
            {kAxisCosThetaJ, 0.0, 1.0, 8, Mapping::linear},
            {kAxisPhi, 0.0, pi, 6, Mapping::linear}};
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  t.value.resize(7 * 8 * 6);
  for (float& v : t.value) v = static_cast<float>(unit(rng));
  t.error.assign(t.value.size(), 0.0f);
  const std::vector<std::size_t> stride = axis_strides(t.axes);
  double reach = 0.0;
  for (std::size_t d = 0; d < 3; ++d) {
    double step = 0.0;
    for (std::size_t m = 0; m < t.value.size(); ++m)
      if ((m / stride[d]) % t.axes[d].count != 0)
        step = std::max(step, static_cast<double>(std::abs(t.value[m] - t.value[m - stride[d]])));
    reach += step;
  }
  bool moved = false;
  for (int p = 0; p < 3000; ++p) {
    const double y[3] = {-1.0 + 2.0 * unit(rng), unit(rng), pi * unit(rng)};
    const double s[3] = {1.0 + (y[0] + 1.0) / 2.0 * 4.0, 1.0 + y[1] * 5.0, 1.0 + y[2] / pi * 3.0};
    double want = 0.0;
    for (int a = 0; a < 7; ++a)
      for (int b = 0; b < 8; ++b)
        for (int e = 0; e < 6; ++e)
          want += t.value[(static_cast<std::size_t>(a) * 8 + b) * 6 + e] * cubic_bspline(s[0] - a) *
                  cubic_bspline(s[1] - b) * cubic_bspline(s[2] - e);
    EXPECT_NEAR(sample_axes(t, y).value, want, 1e-12);
    moved = expect_8bit_lookups_within(t, y, reach, 1e-12, &sample_axes) || moved;
  }
  EXPECT_TRUE(moved);
  EXPECT_EQ(fetches(t), 8);
  t.filter = Filter::texel_fetch;
  EXPECT_EQ(fetches(t), 64);
}

// Two tables share a lookup (the rasterizer sums their entries and looks them up once) exactly
// when every lookup blends the same entries with the same weights: the same law, frame, peak,
// interpolation and axes; the values, the model and the encoding do not matter.
TEST(Table, SameLookupComparesEverythingTheBlendDependsOn) {
  BakeOptions lobe;
  lobe.resolution = {6, 9, 5};
  lobe.tolerance = 1e-4;
  lobe.interpolation = Interpolation::catmull_rom;
  lobe.lobe = tables::LobeFrame{PeakKind::mirror, 0.2};
  const Table a = bake(*parse_model("specular:alpha=100"), Law::g, lobe);
  Table b = bake(*parse_model("backscatter:alpha=8"), Law::g, lobe);
  b.encoding = Encoding::half;
  EXPECT_TRUE(same_lookup(a, b));
  const double y[3] = {0.7, 1.5, 0.4};
  auto nodes = [&](const Table& t) {
    std::vector<std::pair<std::size_t, double>> out;
    EXPECT_TRUE(for_each_node(t, y, [&](std::size_t entry, double w) { out.push_back({entry, w}); }));
    return out;
  };
  const auto na = nodes(a);
  EXPECT_EQ(na, nodes(b));
  EXPECT_GT(na.size(), 27u);  // Catmull–Rom: 4 taps per axis, 3 where an end's missing node folds in
  double blended = 0.0;
  for (const auto& [entry, w] : na) blended += w * a.value[entry];
  EXPECT_EQ(blended, sample_axes(a, y).value);
  auto differs = [&](auto change) {
    Table c = a;
    change(c);
    return !same_lookup(a, c) && !same_lookup(c, a);
  };
  EXPECT_TRUE(differs([](Table& t) { t.peak = PeakKind::retro; }));
  EXPECT_TRUE(differs([](Table& t) { t.frame = Frame::cosines; }));
  EXPECT_TRUE(differs([](Table& t) { t.interpolation = Interpolation::linear; }));
  EXPECT_TRUE(differs([](Table& t) { t.law = Law::a; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes[1].count += 1; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes[1].width *= 2.0; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes[2].max = 3.0; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes[0].min = 0.1; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes[2].mapping = Mapping::cos; }));
  EXPECT_TRUE(differs([](Table& t) { t.axes.pop_back(); }));
  const Table h = bake_table("minnaert:xi=1", Law::h, {9});
  EXPECT_TRUE(differs([&](Table& t) { t = h; }));
}

// A version-1 file (no frame, interpolation or lookup_error attributes) still reads, as the
// cosines frame with linear lookup and its measured interpolation error as its lookup error.
TEST(Table, Version1FilesStillRead) {
  const std::string path = temp_file("v1.exr");
  write_table(bake_table("minnaert:xi=1", Law::h, {9}), path);
  RawExr raw = RawExr::load(path);
  raw.set("ganzfeld.format_version", "1");
  for (const char* name : {"ganzfeld.frame", "ganzfeld.interpolation", "ganzfeld.lookup_error"})
    raw.dropped.insert(name);
  raw.save(path);
  const Table t = read_table(path);
  EXPECT_EQ(t.format_version, 1);
  EXPECT_EQ(t.frame, Frame::cosines);
  EXPECT_EQ(t.interpolation, Interpolation::linear);
  EXPECT_EQ(t.lookup_error, t.interpolation_error);
  // ... and a version-2 file without them is refused.
  raw.set("ganzfeld.format_version", "2");
  raw.save(path);
  EXPECT_THROW(read_table(path), InputError);
}

// bake --max-error: the table meets E, in the lobe frame, and its reported error (the headline)
// covers |lookup - law| at >= 99.9% of fresh random points (another seed than the validation's)
// against direct cubature at 1e-10 (the promise: "reported bound >= actual error at >= 99.9%").
constexpr double kReferenceTol = 1e-10;
constexpr int kFreshPoints = 2000;
constexpr double kAllowedFreshMisses = 0.001;  // the promised 99.9%
/// How many of kFreshPoints seeded points (j·n >= the table's validated minimum) the table's bound
/// misses for any of `roundings` against cubature at kReferenceTol, and the largest error seen.
std::pair<double, double> fresh_misses(const Model& model, Law law, const Table& table, std::uint64_t seed,
                                       std::initializer_list<WeightRounding> roundings) {
  const std::vector<double> x = validation_points(law, kFreshPoints, seed, table.min_cos_j);
  const std::size_t dims = law == Law::g ? 3 : 1;
  std::vector<double> miss(kFreshPoints, 0.0), err(kFreshPoints, 0.0);
  CubatureOptions exact;
  exact.abs_tol = kReferenceTol;
  tbb::parallel_for(0, kFreshPoints, [&](int p) {
    const std::span<const double> q(x.data() + p * dims, dims);
    const Vec3 i = direction_from_cos(law == Law::h ? 1.0 : q[0]);
    const Vec3 j = law == Law::g ? direction_from_cos(q[1], q[2]) : direction_from_cos(q[0]);
    const double truth = evaluate_law(model, law, i, j, exact).value;
    for (WeightRounding r : roundings) err[p] = std::max(err[p], std::abs(sample(table, q, r).value - truth));
    miss[p] = err[p] > table.lookup_error ? 1.0 : 0.0;
  });
  double misses = 0.0, worst = 0.0;
  for (int p = 0; p < kFreshPoints; ++p) {
    misses += miss[p];
    worst = std::max(worst, err[p]);
  }
  return {misses, worst};
}
TEST(Table, MaxErrorBakeReportsAnHonestLookupError) {
  struct Case {
    const char* spec;
    Law law;
    double max_error;
    Encoding encoding = Encoding::single;
  };
  // unorm16 at 5e-5: its rounding (<= 7.6e-6 for a range of 1) is a visible part of E.
  for (const Case& c :
       {Case{"specular:alpha=100", Law::g, 1e-3}, Case{"backscatter:alpha=20", Law::g, 1e-3},
        Case{"specular:alpha=1000", Law::h, 1e-6}, Case{"specular:alpha=1000", Law::h, 5e-5, Encoding::unorm16}}) {
    const ModelPtr model = parse_model(c.spec);
    TargetBake options;
    options.target.lookup_error = c.max_error;
    options.encoding = c.encoding;
    const Table baked = bake(*model, c.law, options);
    const Table table = round_trip(baked, "to_error.exr");
    EXPECT_LE(table.lookup_error, c.max_error) << c.spec;
    EXPECT_GE(table.lookup_error, table.node_error) << c.spec;
    EXPECT_EQ(table.lookup_error, baked.lookup_error) << c.spec;
    EXPECT_EQ(table.target_error, c.max_error) << c.spec;
    EXPECT_EQ(table.frame, c.law == Law::g ? Frame::lobe : Frame::cosines) << c.spec;
    EXPECT_EQ(table.encoding, c.encoding) << c.spec;
    const auto [misses, worst] = fresh_misses(*model, c.law, table, /*seed=*/4242, {WeightRounding::exact});
    std::printf("%s %s: %s nodes, lookup error %.3g, largest fresh error %.3g, %g misses of %d\n", c.spec,
                to_string(c.law),
                resolution_text([&] {
                  std::vector<int> r;
                  for (const Axis& a : table.axes) r.push_back(a.count);
                  return r;
                }())
                    .c_str(),
                table.lookup_error, worst, misses, kFreshPoints);
    EXPECT_LE(misses, kAllowedFreshMisses * kFreshPoints) << c.spec;
  }
}

// --- Format version 4: the warped frame, the hardware filter, the fetch budget --------------

/// A warp with an envelope, a shift and unequal widths that vary over theta_j (what fit_warp
/// returns for a glossy lobe near grazing), for the tests that need no model.
Warp test_warp() {
  Warp w;
  w.mix = kWarpMix;
  w.envelope = 0.1;
  for (int k = 0; k < 5; ++k) w.samples.push_back({0.01 * k, 0.2 + 0.05 * k, 0.2 - 0.03 * k});
  return w;
}

// warped_directions inverts warped_coordinates: the bisection finds psi to ~1e-15 and the offset
// then agrees to a few ulps of its O(1) arithmetic.
constexpr double kWarpRoundTrip = 1e-9;
TEST(Table, WarpedCoordinatesInvertWarpedDirections) {
  Warp warp = test_warp();
  const std::vector<Axis> axes = warped_axes(std::vector<int>{9, 9, 9}, 0.3);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  warp.samples.back().across = 0.01;  // a thin arc at grazing: the whitened beta turns fast near pi/2
  for (double whitening : {0.0, kWarpBetaWhitening})
    for (PeakKind peak : {PeakKind::mirror, PeakKind::retro})
      for (int k = 0; k < 300; ++k) {
        warp.beta_whitening = whitening;
        const double y[3] = {0.01 + 1.5 * u(rng), 0.001 + 0.998 * u(rng), 0.01 + 3.1 * u(rng)};
        const auto [i, j] = warped_directions(peak, warp, axes[0], y[0], y[1], y[2]);
        const std::vector<double> x = coordinates(Law::g, i, j);
        const std::array<double, 3> back = warped_coordinates(peak, warp, axes[0], x[0], x[1], x[2]);
        for (int d = 0; d < 3; ++d) EXPECT_NEAR(back[d], y[d], kWarpRoundTrip) << to_string(peak) << " axis " << d;
      }
  // The whitened beta keeps the ends and pi/2, and rises faster than beta at pi/2 where along > across.
  WarpSample thin{0.0, 1.0, 0.1};
  EXPECT_DOUBLE_EQ(warped_beta(thin, 0.8, 1.0, 0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(warped_beta(thin, 0.8, -1.0, 0.0, pi), pi);
  EXPECT_NEAR(warped_beta(thin, 0.8, 0.0, 1.0, pi / 2), pi / 2, 1e-15);
  EXPECT_GT(warped_beta(thin, 0.8, -0.1, 1.0, std::atan2(1.0, -0.1)) - pi / 2, 2.0 * (std::atan2(1.0, -0.1) - pi / 2));
  // The offset's ends: 1 at the peak (psi = 0), 0 opposite it (psi = pi).
  const WarpSample at = warp_at(warp, axes[0], 0.5);
  EXPECT_DOUBLE_EQ(warped_offset(at, warp.mix, 1.0, 0.0, 0.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(warped_offset(at, warp.mix, -1.0, 0.0, 0.0, pi), 0.0);
}

// A warped, hardware-filtered table survives the file: warp, filter and domain read back exactly,
// and so does every lookup; a broken warp or filter attribute is refused.
TEST_F(TableRefusal, WarpedTableRoundTripsAndBadWarpsAreRefused) {
  const ModelPtr model = parse_model("specular:alpha=100");
  BakeOptions options;
  options.resolution = {9, 13, 7};
  options.tolerance = 1e-6;
  options.lobe = lobe_frame_of(*model);
  options.warped = true;
  options.filter = Filter::hardware;
  const Table baked = bake(*model, Law::g, options);
  EXPECT_EQ(baked.frame, Frame::warped);
  EXPECT_EQ(baked.format_version, kFormatVersion);
  EXPECT_EQ(baked.min_cos_j, kWarpedMinCosJ);
  EXPECT_EQ(baked.warp.samples.size(), static_cast<std::size_t>(baked.axes[0].count));  // one per theta_j node
  EXPECT_GT(baked.warp.envelope, 0.0);  // a Koenderink–Pont lobe's h carries cos theta_j
  const Table t = round_trip(baked, "warped.exr");
  EXPECT_EQ(t.filter, Filter::hardware);
  EXPECT_EQ(t.min_cos_j, baked.min_cos_j);
  EXPECT_EQ(t.warp.mix, baked.warp.mix);
  EXPECT_EQ(t.warp.envelope, baked.warp.envelope);
  EXPECT_EQ(baked.warp.beta_whitening, kWarpBetaWhitening);
  EXPECT_EQ(t.warp.beta_whitening, baked.warp.beta_whitening);
  for (std::size_t k = 0; k < t.warp.samples.size(); ++k) {
    EXPECT_EQ(t.warp.samples[k].shift, baked.warp.samples[k].shift);
    EXPECT_EQ(t.warp.samples[k].along, baked.warp.samples[k].along);
    EXPECT_EQ(t.warp.samples[k].across, baked.warp.samples[k].across);
  }
  const std::vector<double> x = validation_points(Law::g, 50, 77, kWarpedMinCosJ);
  for (int p = 0; p < 50; ++p) {
    const std::span<const double> q(x.data() + 3 * p, 3);
    EXPECT_EQ(sample(t, q).value, sample(baked, q).value);
  }
  const std::string path = temp_file("warped.exr");
  for (const auto& [name, value, fragment] :
       {std::tuple{"ganzfeld.warp", "{\"mix\": 0.85}", "is not {"},
        std::tuple{"ganzfeld.warp", "{\"mix\": 0.85, \"envelope\": 0, \"samples\": [[0, -1, 1], [0, 1, 1]]}",
                   "widths > 0"},
        std::tuple{"ganzfeld.warp", "{\"mix\": 2, \"envelope\": 0, \"samples\": [[0, 1, 1], [0, 1, 1]]}", "mix"},
        std::tuple{"ganzfeld.warp",
                   "{\"mix\": 1, \"envelope\": 0, \"beta_whitening\": 1, \"samples\": [[0, 1, 1], [0, 1, 1]]}",
                   "beta_whitening"},
        std::tuple{"ganzfeld.warp",
                   "{\"mix\": 1, \"envelope\": 0, \"beta_whitening\": \"x\", \"samples\": [[0, 1, 1], [0, 1, 1]]}",
                   "is not {"},
        std::tuple{"ganzfeld.filter", "bilinear", "unknown lookup filter"},
        std::tuple{"ganzfeld.min_cos_j", "1", "validated j"}}) {
    write_table(baked, path);
    RawExr raw = RawExr::load(path);
    raw.set(name, value);
    raw.save(path);
    expect_refused(path, fragment);
  }
  // A version-2 file cannot claim the warped frame or the hardware filter.
  write_table(baked, path);
  RawExr raw = RawExr::load(path);
  raw.set("ganzfeld.format_version", "2");
  raw.save(path);
  expect_refused(path, "need format version 4");
  // Version 4 has the warped frame but no whitened beta axis: such a file is refused, and one whose
  // warp names no beta_whitening reads as beta itself (0), the lookup version-4 readers performed.
  raw.set("ganzfeld.format_version", "4");
  raw.save(path);
  expect_refused(path, "whitened beta axis needs format version 5");
  Table plain = baked;
  plain.warp.beta_whitening = 0.0;
  write_table(plain, path);
  raw = RawExr::load(path);
  raw.set("ganzfeld.format_version", "4");
  raw.save(path);
  const Table v4 = read_table(path);
  EXPECT_EQ(v4.format_version, 4);
  EXPECT_EQ(v4.warp.beta_whitening, 0.0);
}

// The warp is sampled from quartiles of g that vary smoothly over theta_j, and it is interpolated
// between theta_j nodes: noise in its samples is noise in g along theta_j that no interpolation
// follows. Specular alpha = 1000 (a warp ~0.08 wide in cot psi): the second differences of its
// across width over 25 nodes stay below 1e-3 of it (quartiles located to 2e-4 in asinh left 8e-3).
TEST(Table, FittedWarpIsSmoothOverThetaJ) {
  const ModelPtr model = parse_model("specular:alpha=1000");
  const std::optional<LobeFrame> frame = lobe_frame_of(*model);
  ASSERT_TRUE(frame);
  const std::vector<int> counts = {25, 49, 17};
  const std::vector<Axis> axes = warped_axes(counts, kWarpedThetaWidths * frame->width);
  const Warp warp = fit_warp(*model, *frame, axes[0], 1e-6);
  ASSERT_EQ(warp.samples.size(), 25u);
  double width = HUGE_VAL, bend = 0.0;
  for (std::size_t k = 0; k < warp.samples.size(); ++k) width = std::min(width, warp.samples[k].across);
  for (std::size_t k = 1; k + 1 < warp.samples.size(); ++k)
    bend = std::max(bend,
                    std::abs(warp.samples[k - 1].across - 2.0 * warp.samples[k].across + warp.samples[k + 1].across));
  std::printf("across: narrowest %.4g, largest second difference %.3g\n", width, bend);
  EXPECT_LT(bend, 1e-3 * width);
}

/// A warped, hardware-filtered g table of `model` at `counts`: nodes to `tolerance`, validated
/// against cubature at a tenth of it.
BakeOptions warped_hardware_options(const Model& model, std::vector<int> counts, double tolerance) {
  BakeOptions options;
  options.resolution = std::move(counts);
  options.tolerance = tolerance;
  options.check_tolerance = tolerance / 10;
  options.lobe = lobe_frame_of(model);
  options.warped = true;
  options.filter = Filter::hardware;
  return options;
}

// A search that tries one hardware-filtered fetch and then texelFetch of the same grid takes the
// second from the first bake (tables/to_error.cpp): that twin must be exactly the table a
// texelFetch bake makes, its bound the full-precision lookup's alone (not the 8-bit emulations').
TEST(Table, TexelFetchTwinOfAHardwareBakeIsTheTexelFetchBake) {
  const ModelPtr model = parse_model("specular:alpha=8");
  BakeOptions options = warped_hardware_options(*model, {9, 17, 5}, 1e-6);
  options.random_checks = 200;
  Table twin;
  const Table hardware = bake_resolution(*model, Law::g, options, &twin);
  options.filter = Filter::texel_fetch;
  const Table texel_fetch = bake_resolution(*model, Law::g, options);
  EXPECT_EQ(twin.filter, Filter::texel_fetch);
  EXPECT_TRUE(twin.value == texel_fetch.value && twin.error == texel_fetch.error);
  EXPECT_EQ(std::tuple(twin.interpolation_checks, twin.interpolation_error, twin.lookup_error),
            std::tuple(texel_fetch.interpolation_checks, texel_fetch.interpolation_error, texel_fetch.lookup_error));
  EXPECT_LE(twin.interpolation_error, hardware.interpolation_error);
  // Where the 8-bit weights dominate (a fine 1-D table: interpolation falls as h^2, their rounding as h),
  // the twin's bound is the full-precision lookup's, below the hardware filter's.
  BakeOptions fine;
  fine.resolution = {1025};
  fine.tolerance = 1e-10;
  fine.check_tolerance = 1e-11;
  fine.random_checks = 200;
  fine.filter = Filter::hardware;
  Table fine_twin;
  const Table fine_hardware = bake_resolution(*model, Law::h, fine, &fine_twin);
  fine.filter = Filter::texel_fetch;
  EXPECT_EQ(fine_twin.lookup_error, bake_resolution(*model, Law::h, fine).lookup_error);
  std::printf("h at 1025 nodes, interpolation error: texelFetch %.3g, hardware filter %.3g\n",
              fine_twin.interpolation_error, fine_hardware.interpolation_error);
  EXPECT_LT(fine_twin.interpolation_error, 0.5 * fine_hardware.interpolation_error);
}

// GGX towards grazing is a thin arc (across ~ 2 alpha cos theta_j, along ~ 2 alpha): at a fixed
// offset g turns within a few across/along radians of beta = pi/2. The whitened beta axis
// (tables/frame.h, warped_beta) puts the nodes there; with plain beta the same table errs far more.
TEST(Table, WarpedGgxTableErrsLessWithTheWhitenedBeta) {
  const ModelPtr model = parse_model("ggx:roughness=0.3");
  BakeOptions options = warped_hardware_options(*model, {17, 33, 13}, 1e-5);
  const Table whitened = bake(*model, Law::g, options);
  ASSERT_EQ(whitened.warp.beta_whitening, kWarpBetaWhitening);
  options.warp = whitened.warp;
  options.warp->beta_whitening = 0.0;
  const Table plain = bake(*model, Law::g, options);
  std::printf("lookup error: whitened beta %.3g, plain beta %.3g\n", whitened.lookup_error, plain.lookup_error);
  EXPECT_LT(whitened.lookup_error, 0.5 * plain.lookup_error);
}

// The 8-bit emulation: linear weights rounded to multiples of 1/256 (nearest, or down), which
// moves a lookup by at most half (one) step of a cell's difference per axis, and never at nodes.
TEST(Table, HardwareFilterEmulationRoundsTheWeights) {
  EXPECT_EQ(filter_weight(0.3, WeightRounding::exact), 0.3);
  EXPECT_EQ(filter_weight(0.3, WeightRounding::nearest), 77.0 / 256);
  EXPECT_EQ(filter_weight(0.3, WeightRounding::truncate), 76.0 / 256);
  EXPECT_EQ(filter_weight(1.0, WeightRounding::truncate), 1.0);
  const Table table = bake_table("minnaert:xi=0.5", Law::h, {5});
  double largest_step = 0.0;
  for (std::size_t m = 1; m < table.value.size(); ++m)
    largest_step = std::max(largest_step, std::abs(static_cast<double>(table.value[m] - table.value[m - 1])));
  bool moved = false;
  for (int k = 0; k <= 1000; ++k) {
    const double x[1] = {k / 1000.0};
    moved = expect_8bit_lookups_within(table, x, largest_step, 1e-15, &sample) || moved;
  }
  EXPECT_TRUE(moved);
}

// bake --max-error 1e-3 --fetches 1: one hardware-filtered fetch per lookup (the warped frame for
// g of a lobe, the cosines frame for h), the stated bound <= E, and that bound covers the
// full-precision and both 8-bit lookups at >= 99.9% of fresh points (j·n >= the stated minimum)
// against cubature at 1e-10.
TEST(Table, FetchBudgetBakeIsOneFilteredFetchWithAnHonestBound) {
  struct Case {
    const char* spec;
    Law law;
  };
  for (const Case& c : {Case{"specular:alpha=100", Law::g}, Case{"specular:alpha=1000", Law::h}}) {
    const ModelPtr model = parse_model(c.spec);
    TargetBake options;
    options.target = {1e-3, 0, 1};
    const Table table = round_trip(bake(*model, c.law, options), "fetch.exr");
    EXPECT_LE(table.lookup_error, 1e-3) << c.spec;
    EXPECT_EQ(fetches(table), 1) << c.spec;
    EXPECT_EQ(table.filter, Filter::hardware) << c.spec;
    EXPECT_EQ(table.target_fetches, 1) << c.spec;
    EXPECT_EQ(table.frame, c.law == Law::g ? Frame::warped : Frame::cosines) << c.spec;
    const auto [misses, worst] =
        fresh_misses(*model, c.law, table, /*seed=*/4243,
                     {WeightRounding::exact, WeightRounding::nearest, WeightRounding::truncate});
    std::printf("%s %s --fetches 1: lookup error %.3g, largest fresh error %.3g, %zu value bytes, %g misses of %d\n",
                c.spec, to_string(c.law), table.lookup_error, worst, static_cast<std::size_t>(value_bytes(table)),
                misses, kFreshPoints);
    EXPECT_LE(misses, kAllowedFreshMisses * kFreshPoints) << c.spec;
  }
}

// A budget of two fetches for h (one axis): where 8-bit filter weights cannot reach E within the
// bytes (a weight truncated to 1/256 moves a blend by a node step / 256), the same linear blend
// read with texelFetch (2 fetches, full precision) is the pick, with an honest bound.
TEST(Table, FetchBudgetFallsBackToTexelFetchWhereFilterWeightsCannotReach) {
  const ModelPtr model = parse_model("specular:alpha=1000");
  TargetBake options;
  options.target = {1e-5, 1024, 2};
  const Table table = round_trip(bake(*model, Law::h, options), "fetch2.exr");
  EXPECT_LE(table.lookup_error, 1e-5);
  EXPECT_LE(value_bytes(table), 1024u);
  EXPECT_EQ(table.filter, Filter::texel_fetch);
  EXPECT_EQ(table.interpolation, Interpolation::linear);
  EXPECT_EQ(fetches(table), 2);
  EXPECT_EQ(table.target_fetches, 2);
  const auto [misses, worst] = fresh_misses(*model, Law::h, table, /*seed=*/4244, {WeightRounding::exact});
  std::printf(
      "h --max-error 1e-5 --fetches 2 --max-bytes 1024: lookup error %.3g, largest fresh error %.3g, %zu "
      "value bytes, %g misses of %d\n",
      table.lookup_error, worst, static_cast<std::size_t>(value_bytes(table)), misses, kFreshPoints);
  EXPECT_LE(misses, kAllowedFreshMisses * kFreshPoints);
  // One fetch cannot: the refusal names the best it found at one fetch.
  options.target.max_fetches = 1;
  EXPECT_THROW(bake_to_error(*model, Law::h, options), InputError);
}

// bake --max-error 3e-4 --fetches 8 of specular alpha = 100's g: the first pass holds every scheme to
// kCompactValueBytes; one filtered fetch of the warped frame cannot reach 3e-4 there, the b-spline's
// 8 filtered fetches can. Its bound <= E covers the exact and both 8-bit lookups at >= 99.9% of
// fresh points against cubature at 1e-10.
TEST(Table, FetchBudgetOfEightBakesACompactBSpline) {
  const ModelPtr model = parse_model("specular:alpha=100");
  TargetBake options;
  options.target = {3e-4, 0, 8};
  const Table table = round_trip(bake(*model, Law::g, options), "bspline8.exr");
  EXPECT_EQ(table.interpolation, Interpolation::bspline);
  EXPECT_EQ(table.filter, Filter::hardware);
  EXPECT_EQ(fetches(table), 8);
  EXPECT_LE(table.lookup_error, 3e-4);
  EXPECT_LE(value_bytes(table), kCompactValueBytes);
  EXPECT_EQ(table.format_version, kFormatVersion);
  const auto [misses, worst] = fresh_misses(*model, Law::g, table, /*seed=*/4245,
                                            {WeightRounding::exact, WeightRounding::nearest, WeightRounding::truncate});
  std::printf(
      "specular:alpha=100 g --max-error 3e-4 --fetches 8: %s frame, %s, lookup error %.3g, largest fresh error "
      "%.3g, %zu value bytes, %g misses of %d\n",
      to_string(table.frame),
      resolution_text([&] {
        std::vector<int> r;
        for (const Axis& a : table.axes) r.push_back(a.count);
        return r;
      }())
          .c_str(),
      table.lookup_error, worst, static_cast<std::size_t>(value_bytes(table)), misses, kFreshPoints);
  EXPECT_LE(misses, kAllowedFreshMisses * kFreshPoints);
}

TEST(Table, FetchBudgetRefusals) {
  EXPECT_THROW(check_fetch_budget(0), InputError);
  EXPECT_THROW(check_fetch_budget(-3), InputError);
  EXPECT_NO_THROW(check_fetch_budget(1));
  // Within one fetch and 4 kB, 1e-5 is out of reach: the refusal names the best error, its
  // fetches and its bytes.
  const ModelPtr model = parse_model("specular:alpha=8");
  TargetBake options;
  options.target = {1e-5, 4096, 1};
  try {
    bake_to_error(*model, Law::g, options);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("within 1 texture fetch per lookup"), std::string::npos) << what;
    EXPECT_NE(what.find("at 1 fetch in"), std::string::npos) << what;
  }
}

// Schlick's F is affine in f0, so every law of ggx is: g(f0) = (1 - f0) g(0) + f0 g(1) (two tables
// serve every f0; docs/lut-format.md). The cubature's own tolerance bounds the difference.
constexpr double kLinearityTol = 1e-9;
TEST(Table, GgxLawsAreAffineInF0) {
  const ModelPtr g0 = parse_model("ggx:roughness=0.4,f0=0"), g1 = parse_model("ggx:roughness=0.4,f0=1");
  const ModelPtr mid = parse_model("ggx:roughness=0.4,f0=0.3");
  CubatureOptions options;
  options.abs_tol = kLinearityTol;
  for (const auto& [ci, cj, phi] :
       {std::tuple{0.3, 0.8, 0.5}, std::tuple{-0.2, 0.1, 2.5}, std::tuple{0.9, 0.05, 0.0}}) {
    const Vec3 i = direction_from_cos(ci), j = direction_from_cos(cj, phi);
    const double want = 0.7 * vignetting(*g0, i, j, options).value + 0.3 * vignetting(*g1, i, j, options).value;
    EXPECT_NEAR(vignetting(*mid, i, j, options).value, want, 4 * kLinearityTol);
  }
}

TEST(Table, MaxErrorRefusesWhatCannotBeMet) {
  // unorm16's floor is one code step of a range-1 table, 1/65535 (checked first and directly: a
  // wrong floor would otherwise start a long search below it).
  ASSERT_THROW(check_error_target(1.0 / 65536, 0, Law::g, Encoding::unorm16), InputError);
  ASSERT_NO_THROW(check_error_target(1.0 / 65534, 0, Law::g, Encoding::unorm16));
  const ModelPtr model = parse_model("specular:alpha=100");
  auto refused = [&](double e, std::uint64_t bytes, Encoding enc, const std::string& fragment) {
    TargetBake options;
    options.target = {e, bytes, 0};
    options.encoding = enc;
    try {
      bake_to_error(*model, Law::g, options);
      ADD_FAILURE() << "max_error " << e << " max_bytes " << bytes << " accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  refused(0.0, 0, Encoding::single, "expected a positive number");
  refused(-1e-3, 0, Encoding::single, "expected a positive number");
  refused(std::nan(""), 0, Encoding::single, "expected a positive number");
  refused(1e-8, 0, Encoding::single, "below what a float table can hold");
  refused(1e-4, 0, Encoding::half, "below what a half table can hold");
  refused(1e-5, 0, Encoding::unorm16, "below what a unorm16 table can hold");
  refused(1e-3, 100, Encoding::single, "max_bytes=100 is too small");
  refused(1e-6, 4096, Encoding::single, "cannot reach max_error=1e-06");
}

// The library names parameters, not a front end's flags: the command line and a query word the
// same refusal each in its own spelling.
TEST(Table, RefusalsNameParametersThatEachFrontEndSpells) {
  try {
    check_error_target(1e-4, 0, Law::h, Encoding::half);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.refused().parameter, "max_error");
    EXPECT_EQ(e.refused().value, "1e-04");  // format_number: the shortest text that round-trips
    EXPECT_EQ(std::string(e.what()),
              "max_error=1e-04 is below what a half table can hold (its rounding alone); allowed: >= 0.0009765625 "
              "(use encoding=float for less)");
    EXPECT_EQ(e.worded(InputError::flag_spelling),
              "--max-error 1e-04 is below what a half table can hold (its rounding alone); allowed: >= 0.0009765625 "
              "(use --encoding float for less)");
  }
  try {
    parse_resolution("0x0", Law::g);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.worded(InputError::flag_spelling).rfind("--res '0x0' is not a resolution for law g", 0), 0u);
    EXPECT_EQ(e.renamed("res", "res_g").worded(InputError::flag_spelling).rfind("--res-g '0x0' is not", 0), 0u);
    EXPECT_EQ(std::string(e.what()).rfind("res='0x0' is not", 0), 0u);
  }
}

// --max-error under a tight --max-bytes: when the counts the search predicts exceed the cap, it
// bakes the largest table of that shape within the cap, and the refusal names what that reached.
// specular alpha=8 g, E = 1e-5, B = 200000: the first bake (17x17x9 lobe frame, 10 kB) measures
// 1.45e-3; a table within B reaches ~4.3e-5 (docs/tradeoff.md), so a refusal naming an error
// above kCappedBest kept the coarse first bake.
constexpr double kCappedBest = 1e-4;
constexpr std::uint64_t kCap = 200000;
/// The refusal of bake_to_error(options) for `spec`'s g: {best error, its value bytes}, parsed
/// from "the best this search found is E in B value bytes"; fails the test when it is accepted.
std::pair<double, double> refused_best(const std::string& spec, const TargetBake& options) {
  try {
    bake_to_error(*parse_model(spec), Law::g, options);
    ADD_FAILURE() << spec << ": " << options.target.lookup_error << " within " << options.target.max_bytes
                  << " bytes accepted";
  } catch (const InputError& error) {
    const std::string what = error.what();
    std::printf("refused: %s\n", what.c_str());
    const std::string lead = "the best this search found is ";
    const std::size_t at = what.find(lead);
    EXPECT_NE(at, std::string::npos) << what;
    if (at == std::string::npos) return {0.0, 0.0};
    std::size_t used = 0;
    const double best = std::stod(what.substr(at + lead.size()), &used);
    const std::string rest = what.substr(at + lead.size() + used);
    EXPECT_EQ(rest.rfind(" in ", 0), 0u) << what;
    return {best, std::stod(rest.substr(4))};
  }
  return {0.0, 0.0};
}

TEST(Table, MaxErrorUnderATightCapBakesUpToTheCap) {
  TargetBake options;
  options.target = {1e-5, kCap, 0};
  const auto [best, bytes] = refused_best("specular:alpha=8", options);
  EXPECT_LT(best, kCappedBest);
  EXPECT_GT(best, options.target.lookup_error);
  EXPECT_LE(bytes, static_cast<double>(kCap));
}

// A target far out of reach ends the search instead of baking a cap-sized table: hvd-empirical's
// g (discontinuous at the horizon, docs/tradeoff.md) at 1e-4 predicts ~1e19 bytes, and a 64 MiB
// table of it took over 25 minutes on 2 cores before tables::kCapFitReach. The refusal names a
// table of the search's own few bakes, far below the default cap.
constexpr double kHopelessBakeBytes = 1e6;

TEST(Table, MaxErrorFarOutOfReachRefusesWithoutACapSizedBake) {
  TargetBake options;
  options.target.lookup_error = 1e-4;
  const auto [best, bytes] = refused_best("hvd-empirical", options);
  EXPECT_GT(best, options.target.lookup_error);
  EXPECT_GT(bytes, 0.0);
  EXPECT_LT(bytes, kHopelessBakeBytes);
}

// A lookup from directions (law_point's cos and sin phi, the envelope from j's cosine and sine, the
// warp and the theta_j axis sharing one index) lands where the lookup at the table's own axis
// coordinates does, in every frame: the renderer's lookup is the one `sample` and the bound describe.
TEST(Table, LookupFromDirectionsAgreesWithTheAxisCoordinates) {
  const ModelPtr model = parse_model("specular:alpha=100");
  std::vector<Table> tables;
  for (const Frame frame : {Frame::cosines, Frame::lobe, Frame::warped}) {
    BakeOptions options;
    options.resolution = {9, 13, 7};
    options.tolerance = 1e-6;
    if (frame != Frame::cosines) options.lobe = lobe_frame_of(*model);
    options.warped = frame == Frame::warped;
    tables.push_back(bake(*model, Law::g, options));
    ASSERT_EQ(tables.back().frame, frame);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const Table& t : tables) {
    const Lookup lookup(t);
    for (int p = 0; p < 2000; ++p) {
      const Vec3 i = glm::normalize(Vec3{uniform(rng), uniform(rng), uniform(rng)});
      const Vec3 j = glm::normalize(Vec3{uniform(rng), uniform(rng), 0.02 + std::abs(uniform(rng))});
      const Point x = law_point(Law::g, i, j);
      ASSERT_TRUE(x.has_azimuth_trig);
      const Lookup::Site from_directions = lookup.at_law(x);
      const Lookup::Site from_axes = lookup.at_axes(axis_coordinates(t, coordinates(Law::g, i, j)));
      ASSERT_TRUE(from_directions.valid && from_axes.valid);
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(from_directions.u[d], from_axes.u[d], 1e-12) << to_string(t.frame) << d;
      EXPECT_NEAR(from_directions.scale, from_axes.scale, 1e-12) << to_string(t.frame);
      EXPECT_NEAR(sample(t, i, j).value, sample_axes(t, axis_coordinates(t, coordinates(Law::g, i, j))).value, 1e-12);
    }
  }
}

}  // namespace
}  // namespace ganzfeld
