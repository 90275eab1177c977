// The microfacet models (models/ggx.h, models/charlie.h; docs/models.md): values computed by hand,
// reciprocity and positivity, the refusals of the spec, roughness = sqrt(alpha), anisotropy,
// energy (albedo by cubature), the visible-normal density and its sample weights. The
// closed forms (normalization, G1, the white furnace) are `verify` checks (reports/verify_ggx.cpp).
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "integrate/laws.h"
#include "models/charlie.h"
#include "models/ggx.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;
using testing_support::direction_deg;
using testing_support::expect_input_error;
using testing_support::kHandRelative;  // the hand values: Walter eq. 33-34 and Heitz eq. 85-86 with angles

// --- tolerances --------------------------------------------------------------------------------
/// Cubature tolerance for albedos; its estimate bounds the error (integrate/cubature.h).
constexpr double kCubatureTol = 1e-8;
/// Sample weights f (i·n)/pdf against F G2/G1(j): the halfway vector of the draw and the one
/// f recomputes from i + j differ by rounding, amplified by the sharpest lobe (alpha = 0.01).
constexpr double kWeightRelative = 1e-9;
/// The density of visible normals integrates to 1 (Heitz 2018, section 2), to the cubature's
/// tolerance.
constexpr double kDensityTol = 1e-9;

/// Grazing, normal, near-mirror and random directions of the upper hemisphere.
std::vector<Vec3> test_directions() {
  std::vector<Vec3> dirs;
  for (double c : {0.0, 1e-9, 1e-3, 0.5, 1.0})
    for (double phi : {0.0, 90.0, 180.0, 217.0}) dirs.push_back(direction_from_cos(c, phi * pi / 180.0));
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 40; ++k) dirs.push_back(direction_from_cos(u(rng), 2.0 * pi * u(rng)));
  return dirs;
}

const std::vector<std::string> kSpecs{"ggx",
                                      "ggx:alpha=0.001",
                                      "ggx:alpha=1,g2=separable",
                                      "ggx:roughness=0.3,f0=0.04",
                                      "ggx:alpha=1e-200",
                                      "ggx:alpha_x=0.05,alpha_y=0.6,f0=0.5,g2=separable",
                                      "charlie:alpha=0.3",
                                      "charlie:alpha=1e-3"};

TEST(Microfacet, FiniteNonNegativeAndReciprocalToTheBit) {
  const auto dirs = test_directions();
  for (const auto& spec : kSpecs) {
    const ModelPtr m = parse_model(spec);
    // Reciprocal to the bit: symmetric expressions, and Fresnel's i·h computed as |i + j|/2.
    testing_support::expect_finite_non_negative_reciprocal(*m, dirs, spec);
  }
}

TEST(Microfacet, RefusesBadParameters) {
  expect_input_error("ggx:alpha=0", {"ggx", "alpha=0", "(0, 1]"});
  expect_input_error("ggx:alpha=-0.1", {"alpha=-0.1", "(0, 1]"});
  expect_input_error("ggx:alpha=1.5", {"alpha=1.5", "(0, 1]"});
  expect_input_error("ggx:alpha=nan", {"alpha=nan", "not finite", "(0, 1]"});
  expect_input_error("ggx:roughness=0", {"roughness=0", "(0, 1]"});
  expect_input_error("ggx:roughness=1.2", {"roughness=1.2", "(0, 1]"});
  expect_input_error("ggx:roughness=-1", {"roughness=-1", "(0, 1]"});
  expect_input_error("ggx:roughness=1e-200", {"roughness=1e-200", "alpha = R^2 = 0"});
  expect_input_error("ggx:alpha=0.5,roughness=0.5", {"alpha=0.5", "roughness=0.5", "exactly one of"});
  expect_input_error("ggx:alpha=0.5,alpha_x=0.1,alpha_y=0.2", {"alpha=0.5", "alpha_x=0.1", "exactly one of"});
  expect_input_error("ggx:alpha_x=0.1", {"alpha_x=0.1", "needs alpha_y"});
  expect_input_error("ggx:alpha_y=0", {"alpha_y=0", "(0, 1]"});
  expect_input_error("ggx:f0=1.5", {"f0=1.5", "[0, 1]"});
  expect_input_error("ggx:g2=smith", {"g2='smith'", "height-correlated, separable"});
  expect_input_error("ggx:g2=1", {"g2='1'", "height-correlated, separable"});
  expect_input_error("charlie:alpha=0", {"charlie", "alpha=0", "(0, 1]"});
  expect_input_error("charlie:alpha=2", {"alpha=2", "(0, 1]"});
}

// i = (0.6, 0, 0.8), j = (-0.48, 0.6, 0.64): h off every axis, i·h = 0.8.
const Vec3 kI{0.6, 0.0, 0.8}, kJ{-0.48, 0.6, 0.64};

TEST(Microfacet, GgxMatchesHandComputedValues) {
  struct Case {
    const char* spec;
    double f;
  };
  for (const Case& c :
       {Case{"ggx:alpha=0.5,f0=0.04", 0.010582336872287598},
        Case{"ggx:alpha=0.5,f0=0.04,g2=separable", 0.01055561815631517}, Case{"ggx:alpha=0.5", 0.26148999557529561},
        Case{"ggx:alpha_x=0.3,alpha_y=0.6,f0=0.04", 0.018254837583924498},
        Case{"ggx:alpha_x=0.3,alpha_y=0.6,f0=0.04,g2=separable", 0.01823725849517244}})
    EXPECT_NEAR(parse_model(c.spec)->f(kI, kJ), c.f, kHandRelative * c.f) << c.spec;
}

TEST(Microfacet, CharlieMatchesHandComputedValues) {
  EXPECT_NEAR(parse_model("charlie:alpha=0.5")->f(kI, kJ), 0.026229896807741371, kHandRelative * 0.0262);
  EXPECT_NEAR(parse_model("charlie:alpha=0.2")->f(kI, kJ), 0.0027454988781763306, kHandRelative * 0.00275);
}

TEST(Microfacet, RoughnessIsTheSquareRootOfAlpha) {
  const auto dirs = test_directions();
  for (double R : {0.05, 0.3, 0.77, 1.0}) {
    const ModelPtr by_roughness = parse_model("ggx:roughness=" + format_number(R) + ",f0=0.2");
    const ModelPtr by_alpha = parse_model("ggx:alpha=" + format_number(R * R) + ",f0=0.2");
    EXPECT_EQ(by_roughness->spec(), by_alpha->spec());  // one material, one identity
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) ASSERT_EQ(by_roughness->f(i, j), by_alpha->f(i, j)) << R;
  }
}

TEST(Microfacet, AnisotropicWithEqualAlphasIsIsotropic) {
  const auto dirs = test_directions();
  const ModelPtr aniso = parse_model("ggx:alpha_x=0.2,alpha_y=0.2,f0=0.3,g2=separable");
  const ModelPtr iso = parse_model("ggx:alpha=0.2,f0=0.3,g2=separable");
  EXPECT_EQ(aniso->spec(), iso->spec());
  EXPECT_TRUE(aniso->traits().isotropic);
  for (const Vec3& i : dirs)
    for (const Vec3& j : dirs) ASSERT_EQ(aniso->f(i, j), iso->f(i, j));
}

TEST(Microfacet, AnisotropicDependsOnTheAzimuth) {
  const ModelPtr m = parse_model("ggx:alpha_x=0.05,alpha_y=0.5");
  EXPECT_FALSE(m->traits().isotropic);
  // The same pair of directions, rotated by 90 degrees about n: the highlight is wider along y.
  const double along_x = m->f(direction_deg(40, 0), direction_deg(50, 180));
  const double along_y = m->f(direction_deg(40, 90), direction_deg(50, 270));
  EXPECT_GT(std::abs(along_x - along_y), 0.1 * std::max(along_x, along_y));
}

/// The albedo by cubature; it must converge.
Estimate albedo_at(const Model& m, double cos_i) {
  const Estimate a = albedo(m, direction_from_cos(cos_i, 0.4), testing_support::cubature_options(kCubatureTol));
  EXPECT_TRUE(a.converged) << m.spec() << " at cos " << cos_i;
  return a;
}

TEST(Microfacet, GgxAlbedoIsAtMostOneWithUnitFresnel) {
  // f (i·n)/pdf = F G2/G1(j) <= 1 for visible-normal sampling, so a <= 1 (docs/models.md).
  for (const char* spec : {"ggx:alpha=1", "ggx:alpha=0.3", "ggx:alpha=0.01", "ggx:alpha=0.3,g2=separable",
                           "ggx:alpha_x=0.02,alpha_y=0.7"}) {
    const ModelPtr m = parse_model(spec);
    for (double c : testing_support::kIncidenceCosines) {
      const Estimate a = albedo_at(*m, c);
      EXPECT_LE(a.value, 1.0 + a.error) << spec << " at cos " << c;
    }
  }
}

TEST(Microfacet, CharlieAlbedoExceedsOneAtGrazingForSmallAlpha) {
  // Declared not plausible: the Neubelt–Pettineo visibility lets energy grow towards grazing.
  const ModelPtr m = parse_model("charlie:alpha=0.1");
  EXPECT_FALSE(m->traits().energy == EnergyClass::plausible);
  const Estimate a = albedo_at(*m, std::cos(89.0 * pi / 180.0));
  EXPECT_NEAR(a.value, 1.1753640552000465, 10 * kCubatureTol);  // mpmath, docs/models.md
}

TEST(Microfacet, TinyAlphaConvergesWithinBudget) {
  // The mirror limit: the lobe is 0.1 degrees wide; the mass hints put cut lines there.
  const ModelPtr m = parse_model("ggx:alpha=0.001");
  CubatureOptions o = testing_support::cubature_options(1e-9, 1'000'000);
  const Estimate a = albedo(*m, direction_deg(60, 0), o);
  EXPECT_TRUE(a.converged);
  EXPECT_NEAR(a.value, 0.99999749309950543, a.error);  // mpmath in halfway-vector coordinates
  EXPECT_LT(a.evaluations, 200'000);
}

TEST(Microfacet, VisibleNormalDensityIntegratesToOne) {
  for (const ggx::Alpha a : {ggx::Alpha{0.3, 0.3}, ggx::Alpha{0.02, 0.02}, ggx::Alpha{0.05, 0.6}})
    for (double theta : {0.0, 45.0, 80.0, 89.0}) {
      const Vec3 w = direction_deg(theta, 30);
      // ∫ D_visible(w, m) dm over the lune {m·n > 0, m·w > 0} (it vanishes elsewhere).
      const Lune fr = lune(w, Vec3{1.0, 0.0, 0.0});
      std::vector<double> lines{-pi / 2, pi / 2};
      for (double s = 0.25 * std::min(a.x, a.y); s < 1.5; s *= 4.0) {
        lines.push_back(std::atan(s));
        lines.push_back(-std::atan(s));
      }
      const auto F =
          pointwise<2>([&](double t, double phi) { return ggx::D_visible(w, fr.direction(t, phi), a) * std::cos(t); });
      const Estimate e =
          adaptive_cubature<2>(F, {tidy_cuts(lines, -pi / 2, pi / 2, 1e-6), tidy_cuts(lines, fr.phi_lo, pi / 2, 1e-6)},
                               testing_support::cubature_options(kDensityTol * 0.1));
      EXPECT_NEAR(e.value, 1.0, kDensityTol) << a.x << "," << a.y << " at " << theta;
    }
}

TEST(Microfacet, SampleWeightIsFresnelTimesG2OverG1) {
  std::mt19937_64 rng(2018);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const char* spec : {"ggx:alpha=0.3,f0=0.04", "ggx:alpha=0.01,g2=separable", "ggx:alpha_x=0.05,alpha_y=0.6"}) {
    const ModelPtr m = parse_model(spec);
    const auto& ggx_model = dynamic_cast<const Ggx&>(*m);
    for (double theta : {0.0, 50.0, 85.0}) {
      const Vec3 j = direction_deg(theta, 20);
      const double g1_j = ggx::G1(j, ggx_model.alpha());
      for (int s = 0; s < 2000; ++s) {
        const auto draw = m->sample_incident(j, {uniform(rng), uniform(rng), uniform(rng)});
        if (!draw) continue;  // reflected below the horizon
        ASSERT_NEAR(m->pdf_incident(j, draw->i), draw->pdf, 1e-12 * draw->pdf);
        const double weight = m->f(draw->i, j) * draw->i.z / draw->pdf;
        ASSERT_LE(weight, 1.0 + kWeightRelative) << spec;
        // With F = 1 the weight is G2/G1(j) exactly (Heitz 2018, section 2; Walter eq. 14).
        if (std::string(spec).find("f0") == std::string::npos) {
          const auto form = std::string(spec).find("separable") != std::string::npos ? ggx::G2Form::separable
                                                                                     : ggx::G2Form::height_correlated;
          const double G2 = ggx::visibility(draw->i, j, ggx_model.alpha(), form) * 4.0 * draw->i.z * j.z;
          ASSERT_NEAR(weight, G2 / g1_j, kWeightRelative) << spec;
        }
      }
    }
  }
}

}  // namespace
}  // namespace ganzfeld
