// Parameter tables (format version 3) and the engine presets (tables/preset.h): every texel is
// checked against the independent estimator of models/ggx_energy.h (tensor Gauss–Legendre
// over the half vector, written apart from integrate/) or an exact limit; the grid conventions,
// the file round trip and the refusals.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss.hpp>

#include "integrate/laws.h"
#include "models/charlie.h"
#include "models/ggx_energy.h"
#include "models/spec.h"
#include "tables/exr_io.h"
#include "tables/param_table.h"
#include "tables/preset.h"
#include "tests/temp_dir.h"
#include "util/error.h"

namespace ganzfeld::tables {
namespace {

using ggx::charlie_albedo_reference;
using ggx::ggx_albedo_reference;

// Float storage of a value <= 1: half an ulp of 1 (2^-24) is the largest rounding of an exact
// limit value (the errors stored with them say the same).
constexpr double kFloatRounding = 0x1p-24;

/// |table − reference| within the table's stored bound plus the reference's own error estimate.
void expect_within(const ParamTable& t, const std::string& channel, std::size_t m, ggx::ReferenceValue ref) {
  const Channel& ch = t.channels[t.channel_index(channel)];
  EXPECT_LE(std::abs(ch.value[m] - ref.value), ch.error[m] + ref.error)
      << channel << " entry " << m << ": table " << ch.value[m] << " ± " << ch.error[m] << ", reference " << ref.value
      << " ± " << ref.error;
}

PresetOptions options_for(Preset preset, Grid grid, std::vector<int> resolution, const char* axis = kAxisRoughness) {
  PresetOptions o;
  o.preset = preset;
  o.grid = grid;
  o.resolution = std::move(resolution);
  o.axis = axis;
  return o;
}

TEST(TablePreset, DfgNodeGridMatchesTheIndependentReferenceAndTheMirrorLimit) {
  // Node grid 3 x 3: roughness {0, 0.5, 1} (alpha {0, 0.25, 1}) by mu {0, 0.5, 1}.
  const ParamTable t = bake_preset(*parse_model("ggx"), options_for(Preset::dfg, Grid::node, {3, 3}));
  ASSERT_EQ(t.channels.size(), 3u);
  EXPECT_EQ(t.channels[0].name, "dfg_fc");  // Filament's order
  EXPECT_EQ(t.channels[1].name, "dfg_e");
  EXPECT_EQ(t.channels[2].name, "charlie");
  EXPECT_LE(t.node_error, 1e-6);
  for (int k = 0; k < 3; ++k) {  // alpha = 0: the mirror, exact
    const double mu = 0.5 * k;
    EXPECT_NEAR(t.channels[0].value[k], std::pow(1.0 - mu, 5), kFloatRounding);
    EXPECT_EQ(t.channels[1].value[k], 1.0f);
    EXPECT_EQ(t.channels[2].value[k], 0.0f);
  }
  for (int row = 1; row < 3; ++row)
    for (int k = 1; k < 3; ++k) {
      const double alpha = std::pow(0.5 * row, 2), mu = 0.5 * k;
      const std::size_t m = static_cast<std::size_t>(row * 3 + k);
      expect_within(t, "dfg_fc", m, ggx_albedo_reference(mu, alpha, 0.0, false));
      expect_within(t, "dfg_e", m, ggx_albedo_reference(mu, alpha, 1.0, false));
      expect_within(t, "charlie", m, charlie_albedo_reference(mu, alpha));
    }
  // E(mu = 1, alpha = 1) = 1 - ln 2 (F = 1, height-correlated; verify's ggx.furnace.e11).
  EXPECT_NEAR(t.channels[1].value[8], 1.0 - std::numbers::ln2, t.channels[1].error[8]);
}

TEST(TablePreset, CharlieEstimateHoldsWithoutMargin) {
  // The texel (roughness 54.5/64, mu 21.5/64) of the 64 x 64 dfg table where the cubature's own
  // estimate at kPresetTolerance fell 8.5x short of the independent rule (G7/K15 agreeing by
  // chance on a smooth panel not yet in its asymptotic regime); the bound is that estimate, no
  // margin and no tighter tolerance for charlie.
  const double roughness = 54.5 / 64.0, alpha = roughness * roughness, mu = 21.5 / 64.0;
  CubatureOptions o;
  o.abs_tol = kPresetTolerance;
  const Estimate e = albedo(Charlie(alpha), direction_from_cos(mu), o);
  const ggx::ReferenceValue ref = charlie_albedo_reference(mu, alpha);
  EXPECT_TRUE(e.converged);
  EXPECT_LE(std::abs(e.value - ref.value), e.error + ref.error)
      << "engine " << e.value << " ± " << e.error << ", reference " << ref.value << " ± " << ref.error;
}

TEST(TablePreset, Ue4LayoutOnTexelCentresOfAnAlphaAxis) {
  // Texel grid 2 x 2 over alpha: samples at alpha, mu in {0.25, 0.75} (u = (k + 0.5)/2).
  PresetOptions o = options_for(Preset::dfg, Grid::texel, {2, 2}, kAxisAlpha);
  o.layout = DfgLayout::ue4;
  const ParamTable t = bake_preset(*parse_model("ggx:g2=separable"), o);
  ASSERT_EQ(t.channels.size(), 2u);
  EXPECT_EQ(t.model, "ggx:g2=separable");
  for (int row = 0; row < 2; ++row)
    for (int k = 0; k < 2; ++k) {
      const double alpha = 0.25 + 0.5 * row, mu = 0.25 + 0.5 * k;
      const auto e = ggx_albedo_reference(mu, alpha, 1.0, true), fc = ggx_albedo_reference(mu, alpha, 0.0, true);
      const std::size_t m = static_cast<std::size_t>(row * 2 + k);
      expect_within(t, "scale", m, {e.value - fc.value, e.error + fc.error});
      expect_within(t, "bias", m, fc);
    }
}

/// E_avg = 2 ∫ E(mu) mu dmu by Gauss–Legendre over the reference E (panels graded towards 0).
ggx::ReferenceValue e_avg_reference(double alpha) {
  const double cuts[] = {0.0, 0.01, 0.03, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0};
  ggx::ReferenceValue sum;
  for (int p = 0; p + 1 < 9; ++p) {
    auto term = [&](double mu, auto part) { return 2.0 * mu * part(ggx_albedo_reference(mu, alpha, 1.0, false)); };
    sum.value += boost::math::quadrature::gauss<double, 7>::integrate(
        [&](double mu) { return term(mu, [](auto r) { return r.value; }); }, cuts[p], cuts[p + 1]);
    sum.error += boost::math::quadrature::gauss<double, 7>::integrate(
        [&](double mu) { return term(mu, [](auto r) { return r.error; }); }, cuts[p], cuts[p + 1]);
  }
  return sum;
}

TEST(TablePreset, KullaContyEAndEAvg) {
  const ParamTable t = bake_preset(*parse_model("ggx"), options_for(Preset::kulla_conty, Grid::texel, {2, 3}));
  ASSERT_EQ(t.channels.size(), 2u);
  for (int row = 0; row < 2; ++row) {
    const double alpha = std::pow(0.25 + 0.5 * row, 2);
    // The 7-point rule on 8 panels of a smooth E(mu): its own error is far below the table's
    // 1e-7 tolerance; the reference E's estimate is carried.
    const ggx::ReferenceValue avg = e_avg_reference(alpha);
    for (int k = 0; k < 3; ++k) {
      const std::size_t m = static_cast<std::size_t>(row * 3 + k);
      expect_within(t, "e", m, ggx_albedo_reference((k + 0.5) / 3.0, alpha, 1.0, false));
      expect_within(t, "e_avg", m, avg);
    }
  }
}

TEST(TablePreset, GridConventions) {
  const Axis axis{kAxisCosThetaI, 0.0, 1.0, 4, Mapping::linear};
  EXPECT_DOUBLE_EQ(grid_coordinate(axis, Grid::texel, 0), 0.125);  // (k + 0.5)/N
  EXPECT_DOUBLE_EQ(grid_coordinate(axis, Grid::texel, 3), 0.875);
  EXPECT_DOUBLE_EQ(grid_coordinate(axis, Grid::node, 3), 1.0);  // k/(N - 1)
  EXPECT_DOUBLE_EQ(grid_position(axis, Grid::texel, 0.125), 0.0);
  EXPECT_DOUBLE_EQ(grid_position(axis, Grid::texel, 0.0), 0.0);  // clamp to edge
  EXPECT_DOUBLE_EQ(grid_position(axis, Grid::texel, 0.5), 1.5);
  EXPECT_DOUBLE_EQ(grid_position(axis, Grid::node, 0.5), 1.5);
  EXPECT_DOUBLE_EQ(alpha_of(kAxisRoughness, 0.5), 0.25);
  EXPECT_DOUBLE_EQ(alpha_of(kAxisAlpha, 0.5), 0.5);
}

/// A 3 x 4 texel table whose channel is v = x + 10 mu: bilinear lookup reproduces it exactly
/// between texel centres.
ParamTable linear_table() {
  ParamTable t;
  t.preset = "dfg";
  t.layout = "filament";
  t.model = "ggx:g2=height-correlated";
  t.axes = {{kAxisRoughness, 0.0, 1.0, 3, Mapping::linear}, {kAxisCosThetaI, 0.0, 1.0, 4, Mapping::linear}};
  t.tolerance = 1e-7;
  Channel ch{"e", "test", {}, {}, 0};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) {
      ch.value.push_back(
          static_cast<float>(grid_coordinate(t.axes[0], t.grid, r) + 10.0 * grid_coordinate(t.axes[1], t.grid, k)));
      ch.error.push_back(1e-7f);
    }
  ch.lookup_error = 2e-7;
  t.node_error = 1e-7f;
  t.lookup_error = 2e-7;
  t.lookup_checks = 1;
  t.channels.push_back(ch);
  return t;
}

TEST(TablePreset, BilinearLookupOnTexelCentres) {
  const ParamTable t = linear_table();
  constexpr double kFloat = 1e-6;  // float storage of values up to 11
  EXPECT_NEAR(sample_param(t, 0, 0.5, 0.5).value, 0.5 + 5.0, kFloat);
  EXPECT_NEAR(sample_param(t, 0, 0.3, 0.7).value, 0.3 + 7.0, kFloat);
  // Outside the texel centres the edge texel is read (clamp to edge).
  EXPECT_NEAR(sample_param(t, 0, 0.0, 0.0).value, 1.0 / 6 + 10.0 / 8, kFloat);
  EXPECT_NEAR(sample_param(t, 0, 1.0, 1.0).value, 5.0 / 6 + 70.0 / 8, kFloat);
  EXPECT_NEAR(sample_param(t, 0, 0.3, 0.7).error, 1e-7, 1e-12);
}

TEST(TablePreset, FileRoundTripAndVersionSeparation) {
  ParamTable t = linear_table();
  t.command = "ganzfeld test";
  t.version = "0";
  const std::string path = testing_support::temp_dir() + "/param.exr";
  write_param_table(t, path);
  EXPECT_EQ(format_version_of(path), 3);
  const ParamTable back = read_param_table(path);
  EXPECT_EQ(back.channels[0].value, t.channels[0].value);
  EXPECT_EQ(back.channels[0].error, t.channels[0].error);
  EXPECT_EQ(back.axes[1].count, 4);
  EXPECT_EQ(back.grid, Grid::texel);
  EXPECT_EQ(back.command, t.command);
  EXPECT_EQ(back.channels[0].lookup_error, t.channels[0].lookup_error);
  EXPECT_EQ(back.lookup_error, t.lookup_error);
  EXPECT_EQ(back.lookup_checks, t.lookup_checks);
  EXPECT_THROW(read_table(path), InputError);  // the version 1/2 reader refuses version 3
  // Half tables: the baker rounds to half; the file holds exactly those numbers.
  PresetOptions half = options_for(Preset::kulla_conty, Grid::node, {2, 3}, kAxisAlpha);
  half.encoding = Encoding::half;
  const ParamTable h = bake_preset(*parse_model("ggx"), half);
  write_param_table(h, testing_support::temp_dir() + "/half.exr");
  const ParamTable h_back = read_param_table(testing_support::temp_dir() + "/half.exr");
  EXPECT_EQ(h_back.encoding, Encoding::half);
  EXPECT_EQ(h_back.channels[0].value, h.channels[0].value);
  EXPECT_EQ(h_back.channels[1].error, h.channels[1].error);
  ParamTable understated = t;  // a lookup error below the texels' own is refused, never written
  understated.channels[0].lookup_error = understated.lookup_error = 0.5e-7;
  EXPECT_THROW(write_param_table(understated, testing_support::temp_dir() + "/understated.exr"), InputError);
  t.channels[0].value[5] = std::nanf("");
  EXPECT_THROW(write_param_table(t, testing_support::temp_dir() + "/nan.exr"), InputError);
  EXPECT_FALSE(std::filesystem::exists(testing_support::temp_dir() + "/nan.exr"));
}

// The headline of a parameter table is its validated lookup error (as for every table): at fresh seeded points over the
// validated domain, |bilinear lookup - independent reference| stays within each channel's lookup_error at >= 99.9% of
// them (all of them, in practice). A coarse 8 x 8 table so that interpolation, not the cubature, dominates.
TEST(TablePreset, LookupErrorBoundsFreshPoints) {
  constexpr int kPoints = 300;
  constexpr double kCoverage = 0.999;  // the promise: the bound holds at >= 99.9% of fresh points
  for (const Grid grid : {Grid::texel, Grid::node}) {
    const ParamTable t = bake_preset(*parse_model("ggx"), options_for(Preset::dfg, grid, {8, 8}));
    std::mt19937_64 rng(20261125);
    std::uniform_real_distribution<double> roughness(std::sqrt(kMinValidatedAlpha), 1.0), mu(kMinValidatedMu, 1.0);
    std::vector<int> outside(t.channels.size(), 0);
    double largest_ratio = 0.0;
    for (int p = 0; p < kPoints; ++p) {
      const double r = roughness(rng), m = mu(rng), alpha = r * r;
      const ggx::ReferenceValue refs[] = {ggx_albedo_reference(m, alpha, 0.0, false),
                                          ggx_albedo_reference(m, alpha, 1.0, false),
                                          charlie_albedo_reference(m, alpha)};
      for (std::size_t c = 0; c < t.channels.size(); ++c) {
        const double actual = std::abs(sample_param(t, c, r, m).value - refs[c].value);
        largest_ratio = std::max(largest_ratio, actual / t.channels[c].lookup_error);
        outside[c] += actual > t.channels[c].lookup_error + refs[c].error;
      }
    }
    for (std::size_t c = 0; c < t.channels.size(); ++c) {
      EXPECT_LE(outside[c], kPoints * (1.0 - kCoverage))
          << t.channels[c].name << " on the " << to_string(grid) << " grid";
      // The bound is a bound of this table's interpolation, not the per-texel cubature error.
      EXPECT_GT(t.channels[c].lookup_error, 100 * t.node_error) << t.channels[c].name;
    }
    std::printf("%s grid 8x8: largest |lookup - reference| / lookup_error %.3f; lookup_error %.3g over %lld points\n",
                to_string(grid), largest_ratio, t.lookup_error, t.lookup_checks);
  }
}

TEST(TablePreset, Refusals) {
  const PresetOptions dfg = options_for(Preset::dfg, Grid::texel, {2, 2});
  EXPECT_THROW(bake_preset(*parse_model("lambert"), dfg), InputError);
  EXPECT_THROW(bake_preset(*parse_model("ggx:alpha_x=0.2,alpha_y=0.4"), dfg), InputError);
  EXPECT_THROW(bake_preset(*parse_model("charlie"), dfg), InputError);
  EXPECT_THROW(bake_preset(*parse_model("ggx"), options_for(Preset::dfg, Grid::texel, {2, 2}, "beta")), InputError);
  EXPECT_THROW(bake_preset(*parse_model("ggx"), options_for(Preset::dfg, Grid::texel, {1, 2})), InputError);
  EXPECT_THROW(parse_preset_resolution("1"), InputError);
  EXPECT_THROW(parse_preset_resolution("4x4x4"), InputError);
  EXPECT_THROW(parse_preset("lambert"), InputError);
  EXPECT_THROW(parse_grid("centre"), InputError);
  EXPECT_EQ(parse_preset_resolution("8x16"), (std::vector<int>{8, 16}));
  // eval --alpha/--roughness: a model without that parameter, a mixture.
  EXPECT_THROW(with_parameter(parse_spec("lambert"), "alpha", 0.5), InputError);
  EXPECT_THROW(with_parameter(parse_spec("specular:alpha=8"), "roughness", 0.5), InputError);
  EXPECT_THROW(with_parameter(parse_spec("specular:alpha=8"), "alpha", 0.5), InputError);  // alpha in [1, 10000]
  EXPECT_THROW(with_parameter(parse_spec("0.5*ggx + 0.5*lambert"), "alpha", 0.5), InputError);
  EXPECT_EQ(spec_text(with_parameter(parse_spec("ggx:roughness=0.2,f0=0.04"), "alpha", 0.5)), "ggx:alpha=0.5,f0=0.04");
  EXPECT_EQ(spec_text(with_parameter(parse_spec("ggx:alpha_x=0.1,alpha_y=0.3"), "roughness", 0.5)),
            "ggx:roughness=0.5");
}

}  // namespace
}  // namespace ganzfeld::tables
