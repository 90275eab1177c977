// The catalogue's later models (docs/models.md): Ashikhmin–Shirley (models/ashikhmin_shirley.h),
// Schlick 1994 and Schlick's rational Phong (models/schlick.h, models/classic_models.h), Kajiya's
// fibre case (models/kajiya.h), and He–Torrance's mirror delta in renders and exports
// (Model::mirror_reflectance). Values against an independent evaluation (mpmath, 30 digits, the
// formulas written with angles), traits measured, parameters validated, energy by cubature.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "export/glsl.h"
#include "integrate/laws.h"
#include "models/ashikhmin_shirley.h"
#include "models/he_torrance.h"
#include "models/registry.h"
#include "models/schlick.h"
#include "models/spec.h"
#include "rasterizer/shading.h"
#include "scene/scene.h"
#include "tables/bake.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;
using testing_support::direction_deg;
using testing_support::expect_input_error;
using testing_support::kHandRelative;

/// Cubature tolerance of the energy checks and the slack they are compared with (ten times it).
constexpr double kCubatureTol = 1e-8;
constexpr double kEnergySlack = 10 * kCubatureTol;
/// A model declared anisotropic or non-reciprocal must show at least this relative change.
constexpr double kEvidence = 0.1;

// The pairs of the mpmath values: computed at 30 digits from the headers' formulas written with
// angles (the azimuth of h by atan2, the angles to the fibre axis by acos), not with the code.
const Vec3 kI1 = direction_deg(40, 20), kJ1 = direction_deg(55, 215), kI2 = direction_deg(30, 0),
           kJ2 = direction_deg(35, 170);

TEST(CatalogueModels, ValuesAgainstAnIndependentEvaluation) {
  const struct {
    const char* spec;
    Vec3 i, j;
    double expected;
  } cases[] = {
      {"ashikhmin-shirley:rd=0.5,rs=0.05,nu=100,nv=100", kI1, kJ1, 0.202000238275423543157305358232},
      {"ashikhmin-shirley:rd=0.3,rs=0.2,nu=10,nv=1000", kI2, kJ2, 0.279767914769279951124234431247},
      {"schlick:c=0.5,r=0.1,p=1", kI2, kJ2, 0.497376892289920794364745291123},
      {"schlick:c=0.2,r=0.3,p=0.25", kI2, kJ2, 0.0651902309899491862289498634843},
      {"kajiya:kd=0.3,ks=0.7,n=20", kI2, kJ2, 0.857597767546621264461777971771},
      {"kajiya:kd=0.3,ks=0.7,n=20", kJ2, kI2, 0.901910078289281045589801279862},
      {"schlick-phong:kd=0.5,ks=0.5,n=20", kI2, kJ2, 0.654909639858195928277008957778},
  };
  for (const auto& c : cases)
    EXPECT_NEAR(parse_model(c.spec)->f(c.i, c.j), c.expected, kHandRelative * c.expected) << c.spec;
}

TEST(CatalogueModels, ParametersAreValidated) {
  expect_input_error("ashikhmin-shirley:rs=1.5", {"ashikhmin-shirley", "rs=1.5", "[0, 1]"});
  expect_input_error("ashikhmin-shirley:nu=-1", {"nu=-1", "[0, 10000]"});
  expect_input_error("ashikhmin-shirley:n=10", {"ashikhmin-shirley", "n"});
  expect_input_error("schlick:r=0", {"schlick", "r=0", "(0, 1]"});
  expect_input_error("schlick:p=0", {"p=0", "(0, 1]"});
  expect_input_error("schlick:alpha=0.5", {"schlick", "alpha"});
  expect_input_error("kajiya:kd=0.6,ks=0.6", {"kajiya", "kd=0.6", "ks=0.6", "<= 1"});
  expect_input_error("kajiya:n=0.5", {"n=0.5", "[1, 10000]"});
  expect_input_error("schlick-phong:kd=0.7,ks=0.7", {"schlick-phong", "<= 1"});
}

std::vector<Vec3> test_directions() {
  std::vector<Vec3> dirs;
  for (double t : {0.0, 1e-7, 20.0, 45.0, 70.0, 89.0, 89.999, 90.0})
    for (double p : {0.0, 33.0, 90.0, 160.0, 181.0, 270.0}) dirs.push_back(direction_deg(t, p));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k) dirs.push_back(sample_cosine(u(rng), u(rng)));
  return dirs;
}

TEST(CatalogueModels, FiniteNonNegativeAndTraitsAsMeasured) {
  const std::vector<Vec3> dirs = test_directions();
  for (const std::string spec :
       {"ashikhmin-shirley", "ashikhmin-shirley:nu=0,nv=10000", "ashikhmin-shirley:nu=10000,nv=10000,rs=1",
        "ashikhmin-shirley:nu=0,nv=0,rd=1,rs=0", "schlick", "schlick:r=0.001,p=0.001", "schlick:r=1,c=1",
        "schlick:p=0.3", "kajiya", "kajiya:n=10000", "kajiya:kd=1,ks=0", "schlick-phong", "schlick-phong:n=10000"}) {
    const ModelPtr m = parse_model(spec);
    const Traits traits = m->traits();
    double asymmetry = 0.0, anisotropy = 0.0;
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        const double f = m->f(i, j);
        ASSERT_TRUE(std::isfinite(f)) << spec;
        ASSERT_GE(f, 0.0) << spec;
        if (traits.reciprocal) { ASSERT_EQ(f, m->f(j, i)) << spec << ": reciprocal to the bit"; }
        const double scale = std::max({f, m->f(j, i), 1e-6});
        asymmetry = std::max(asymmetry, std::abs(f - m->f(j, i)) / scale);
        // A rotation of the pair by 0.7 rad about n.
        const double c = std::cos(0.7), s = std::sin(0.7);
        const Vec3 ri{c * i.x - s * i.y, s * i.x + c * i.y, i.z}, rj{c * j.x - s * j.y, s * j.x + c * j.y, j.z};
        const double fr = m->f(ri, rj);
        if (i.z > 1e-3 && j.z > 1e-3) anisotropy = std::max(anisotropy, std::abs(f - fr) / std::max({f, fr, 1e-6}));
      }
    if (!traits.reciprocal) { EXPECT_GT(asymmetry, kEvidence) << spec; }
    if (traits.isotropic) {
      EXPECT_LT(anisotropy, 1e-9) << spec;
    } else {
      EXPECT_GT(anisotropy, kEvidence) << spec;
    }
  }
  EXPECT_TRUE(parse_model("ashikhmin-shirley:nu=10,nv=10")->traits().isotropic);
  EXPECT_FALSE(parse_model("ashikhmin-shirley:nu=10,nv=11")->traits().isotropic);
  EXPECT_TRUE(parse_model("schlick:p=1")->traits().isotropic);
}

Estimate albedo_of(const std::string& spec, double cos_i, double phi = 0.4) {
  CubatureOptions o;
  o.abs_tol = kCubatureTol;
  const Estimate e = albedo(*parse_model(spec), direction_from_cos(cos_i, phi), o);
  EXPECT_TRUE(e.converged) << spec << " at cos " << cos_i;
  return e;
}

TEST(AshikhminShirley, DiffuseAndSpecularEnergy) {
  // rho_d alone (rs = 1 leaves no diffuse; rd = 1, rs = 0 with nu = nv = 10000: the specular
  // part is a narrow lobe whose albedo is F(k.h ~ cos theta_i) times the fraction reflected above
  // the horizon): the diffuse albedo is (1 - rs) rd (1 - (1 - mu/2)^5), the paper's constant.
  for (double mu : {1.0, 0.5, 0.1}) {
    const ModelPtr m = parse_model("ashikhmin-shirley:rd=1,rs=0.3,nu=50,nv=50");
    const auto& as = dynamic_cast<const AshikhminShirley&>(*m);
    CubatureOptions o;
    o.abs_tol = kCubatureTol;
    const Vec3 i = direction_from_cos(mu, 0.2);
    // The diffuse term alone, as its own model would be integrated.
    class DiffuseOnly final : public Model {
     public:
      explicit DiffuseOnly(const AshikhminShirley& m) : m_(m) {}
      std::string spec() const override { return "diffuse part"; }
      Traits traits() const override { return {}; }
      double f(const Vec3& a, const Vec3& b) const noexcept override { return m_.diffuse(a, b); }
      const AshikhminShirley& m_;
    } diffuse(as);
    const Estimate e = albedo(diffuse, i, o);
    const double x = 1.0 - 0.5 * mu;
    EXPECT_NEAR(e.value, 0.7 * (1.0 - x * x * x * x * x), kEnergySlack) << mu;
  }
  // The specular term's sampling weight F (i.n)/max(i.n, j.n) <= F <= 1: with rs = 1 (F = 1) and
  // no diffuse part the albedo stays below 1 at every incidence.
  for (double mu : testing_support::kIncidenceCosines)
    EXPECT_LT(albedo_of("ashikhmin-shirley:rd=0,rs=1,nu=100,nv=10", mu).value, 1.0 + kEnergySlack) << mu;
}

TEST(AshikhminShirley, HalfwayDrawsHaveThePrintedDensity) {
  // The weight of a specular draw is exactly F (i.n)/max(i.n, j.n) with rd = 0 (no diffuse
  // draws): the draw's density is the one pdf_incident reports and f is built on.
  const ModelPtr m = parse_model("ashikhmin-shirley:rd=0,rs=0.3,nu=20,nv=500");
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double theta : {0.0, 40.0, 80.0}) {
    const Vec3 j = direction_deg(theta, 70.0);
    int drawn = 0;
    for (int s = 0; s < 5000; ++s) {
      const auto draw = m->sample_incident(j, {u(rng), u(rng), u(rng)});
      if (!draw) continue;
      ++drawn;
      const Vec3 h = glm::normalize(draw->i + j);
      const double kh = glm::dot(j, h), F = 0.3 + 0.7 * std::pow(1.0 - kh, 5);
      const double weight = m->f(draw->i, j) * draw->i.z / draw->pdf;
      ASSERT_NEAR(weight, F * draw->i.z / std::max(draw->i.z, j.z), 1e-12) << theta;
    }
    EXPECT_GT(drawn, 1000) << theta;
  }
}

TEST(Schlick, NormalizedAzimuthKeepsZsEnergy) {
  // ∫ Z(t) A(w)/a(p) t dω = pi for every p (the printed A alone gives pi a(p): docs/errata.md).
  for (double p : {1.0, 0.3, 0.02}) {
    const double a = schlick::azimuth_mean(p);
    CubatureOptions o;
    o.abs_tol = 1e-10;
    const Lune hemi = lune(Vec3{0, 0, 1}, Vec3{1, 0, 0});
    std::vector<double> lines{-pi / 2, pi / 2};
    for (double d : {p / 4, p, 4 * p, 0.1}) lines.insert(lines.end(), {std::atan(d), -std::atan(d)});
    const auto integrand = pointwise<2>([&](double t, double phi) {
      const Vec3 h = hemi.direction(t, phi);
      const double s = std::hypot(h.x, h.y), w = s > 0.0 ? h.x / s : 1.0;
      return schlick::zenith(h.z, 0.2) * schlick::azimuth(w, p) / a * h.z * std::cos(t);
    });
    const Estimate e = adaptive_cubature<2>(
        integrand, {tidy_cuts(lines, -pi / 2, pi / 2, 1e-6), tidy_cuts(lines, -pi / 2, pi / 2, 1e-6)}, o);
    EXPECT_NEAR(e.value, pi, 10 * e.error + 1e-9) << p;
  }
  EXPECT_NEAR(schlick::azimuth_mean(0.5), 0.970773111746018, 1e-14);  // mpmath: (2/pi) sqrt(p) K(1 - p^2)
}

TEST(Schlick, RationalApproximations) {
  // Kernel conditions of the rational Phong lobe: S(0) = 0, S(1) = 1, S'(1) = n.
  for (double n : {1.0, 20.0, 1000.0}) {
    EXPECT_EQ(schlick::rational_phong(0.0, n), 0.0);
    EXPECT_EQ(schlick::rational_phong(1.0, n), 1.0);
    const double h = 1e-7;
    EXPECT_NEAR((schlick::rational_phong(1.0, n) - schlick::rational_phong(1.0 - h, n)) / h, n, 1e-5 * n * n) << n;
  }
  // Schlick's Fresnel factor at its ends and Z as pi times GGX with alpha^2 = r.
  EXPECT_EQ(schlick::fresnel(1.0, 0.04), 0.04);
  EXPECT_EQ(schlick::fresnel(0.0, 0.04), 1.0);
  EXPECT_NEAR(schlick::zenith(0.8, 0.09), 0.09 / std::pow(1.0 + (0.09 - 1.0) * 0.64, 2), 1e-15);
}

TEST(Schlick, InterreflectionTermIsNotPlausible) {
  // The shadowed light returned as (1 - G G')/(4 pi v v') has an albedo ~ 1/(2 v) at grazing.
  EXPECT_LT(albedo_of("schlick:c=1,r=0.1", 1.0).value, 1.0);
  EXPECT_GT(albedo_of("schlick:c=1,r=0.1", 0.01).value, 1.0);
}

TEST(Kajiya, HighlightIsTheConeOfMirrorDirectionsAboutTheFibres) {
  const ModelPtr m = parse_model("kajiya:kd=0,ks=1,n=1000");
  // j on the cone k.x = -i.x: the highlight's maximum, ks/(i.n), at every point of the cone.
  const Vec3 i = direction_deg(50, 30);
  const double s = std::hypot(i.y, i.z);
  for (double beta : {0.3, 1.0, 2.0, 2.8}) {
    const Vec3 j{-i.x, s * std::cos(beta), s * std::sin(beta)};
    EXPECT_NEAR(m->f(i, j), 1.0 / i.z, 1e-9 / i.z) << beta;
  }
  // Off the cone it falls: 0.1 rad off, cos^1000 = exp(-5).
  const Vec3 off{-i.x + 0.1, s * std::cos(1.0), s * std::sin(1.0)};
  EXPECT_LT(m->f(i, glm::normalize(off)), 0.1 / i.z);
  // The diffuse term follows the width of the fibres seen from i: sin(t, i)/pi/(i.n).
  const ModelPtr d = parse_model("kajiya:kd=1,ks=0");
  EXPECT_NEAR(d->f(i, direction_deg(10, 0)), std::hypot(i.y, i.z) / pi / i.z, 1e-15);
}

// Whether its laws come from cubature or from tables (summed with other lobes' tables in a prepared
// material: rasterizer/shading.h), the delta is added once, apart from them.
TEST(HeTorranceMirrorDelta, RenderAddsItUnderExtendedSources) {
  const ModelPtr m = parse_model("he-torrance:sigma0=0.02");
  const auto& ht = dynamic_cast<const HeTorrance&>(*m);
  const Vec3 n{0, 0, 1}, t{1, 0, 0}, j = direction_deg(50, 0);
  const double rho = ht.specular_reflectance(j.z);
  ASSERT_GT(rho, 0.01);
  EXPECT_TRUE(has_mirror_delta(*m));
  tables::BakeOptions small;
  small.tolerance = 1e-5;
  small.resolution = {5, 5, 3};
  const auto g = std::make_shared<const tables::Table>(tables::bake(*m, Law::g, small));
  small.resolution = {9};
  const auto h = std::make_shared<const tables::Table>(tables::bake(*m, Law::h, small));
  for (const raster::LawSourcePtr& laws : {raster::direct_laws(m, 1e-7), raster::table_laws(g, h)}) {
    raster::ShadingLobe lobe;
    lobe.model = m;
    lobe.laws = laws;
    const raster::ShadingMaterial material{lobe};
    Light ganzfeld;
    ganzfeld.type = Light::Type::ganzfeld;
    EXPECT_NEAR(raster::shade(material, {ganzfeld}, n, j, t)[0], lobe.laws->h(j) + rho, 1e-12);
    // A sky whose pole sees mirror(j) = (-sin 50, 0, cos 50), and one that does not.
    Light sky;
    sky.type = Light::Type::hemispherical;
    sky.direction = direction_deg(40, 180);
    EXPECT_NEAR(raster::shade(material, {sky}, n, j, t)[0], lobe.laws->g(sky.direction, j) + rho, 1e-12);
    sky.direction = direction_deg(60, 0);
    ASSERT_LT(glm::dot(mirror(j), sky.direction), 0.0);
    EXPECT_NEAR(raster::shade(material, {sky}, n, j, t)[0], lobe.laws->g(sky.direction, j), 1e-12);
  }
  // Models without a mirror term add nothing; a mixture adds its weighted share.
  EXPECT_EQ(parse_model("ggx")->mirror_reflectance(0.5), 0.0);
  EXPECT_FALSE(has_mirror_delta(*parse_model("ggx")));
  EXPECT_NEAR(parse_model("0.25*he-torrance:sigma0=0.02 + 0.75*lambert")->mirror_reflectance(j.z), 0.25 * rho, 1e-15);
}

TEST(HeTorranceMirrorDelta, ExportRefusesWhatItWouldLeaveOut) {
  // The scene shader samples tables of f; the delta render adds under a sky is in none of them.
  Scene scene;
  scene.materials.push_back({"coat", {{1.0, "he-torrance", parse_model("he-torrance"), {1, 1, 1}}}});
  scene.objects.push_back({});
  scene.lights.push_back(grey_light(Light::Type::hemispherical, Vec3{0, 1, 0}, 1.0));
  try {
    exporting::check_scene_exportable(scene);
    ADD_FAILURE() << "a he-torrance lobe under a sky was exported without its mirror delta";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mirror delta"), std::string::npos) << e.what();
  }
  scene.materials[0].lobes[0] = {1.0, "lambert", parse_model("lambert"), {1, 1, 1}};
  EXPECT_NO_THROW(exporting::check_scene_exportable(scene));
}

}  // namespace
}  // namespace ganzfeld
