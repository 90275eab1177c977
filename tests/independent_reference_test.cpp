// g and h of every Koenderink–Pont lobe, both halfway-vector-disk models, five classic models and
// the catalogue's later ones (Ashikhmin–Shirley, Schlick 1994, Schlick's rational Phong, Kajiya)
// against a reference that is not ganzfeld's engine: reference/ (Boost.Math's adaptive
// gauss_kronrod<61>, nested, on the lune written out from its definition apart from integrate/,
// with break points at the directions where each lobe peaks). The engine's answer must agree
// within its own error estimate plus the reference's.
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "integrate/laws.h"
#include "models/kp_lobes.h"
#include "models/spec.h"
#include "reference/lune_reference.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;
constexpr double kEngineTol = 1e-8, kReferenceTol = 1e-10;

/// The reference as this test first pinned it: break points at the mirror and view directions
/// only (not the model's mass hints), each panel to its own relative tolerance, so its figures
/// are those this test has always pinned.
reference::Options pinned_reference_options() {
  reference::Options options;
  options.tolerance = kReferenceTol;
  options.use_mass_hints = false;
  options.global_tolerance = false;
  return options;
}

const std::vector<std::string>& models() {
  static const std::vector<std::string> specs{"lambert",
                                              "minnaert:xi=0.3",
                                              "minnaert:xi=2",
                                              "specular:alpha=8",
                                              "specular:alpha=100",
                                              "backscatter:alpha=8",
                                              "perfect-backscatter:alpha=3",
                                              "asperity:alpha=4",
                                              "hvd-empirical:cd=0.5,f0=0.3,k=0.3,ns=20,nr=10",
                                              "hvd-fit:cd=0.5,f0=0.05,f90=1,k=0.4,n1=20,r1=0.3,n2=10,r2=0.4",
                                              "phong-lewis",
                                              "blinn-phong",
                                              "cook-torrance",
                                              "oren-nayar",
                                              "ward",
                                              "ggx:alpha=0.3"};
  return specs;
}

/// Cases where the engine's estimate is below its actual error against this reference. Listed,
/// not hidden: the test fails if the list changes either way. Empty since the panel estimate
/// became the larger of |K⊗K − G⊗G| and the per-axis differences' sum (integrate/cubature.cpp):
/// the raw difference undershot cook-torrance g at theta_i 35, theta_j 70, phi 0 by 30%.
const std::set<std::string> kKnownDishonest{};

/// Records `what` in `dishonest` when the engine's answer is further from the reference than
/// the engine's own estimate plus the reference's; a non-converged answer fails outright.
void check_agreement(const std::string& what, const Estimate& engine, const reference::Value& reference,
                     std::set<std::string>& dishonest) {
  EXPECT_TRUE(engine.converged) << what;
  if (std::abs(engine.value - reference.value) <= engine.error + reference.error + 1e-13) return;
  dishonest.insert(what);
  std::printf("dishonest: %s: engine %.17g ± %.3g, reference %.17g ± %.3g\n", what.c_str(), engine.value, engine.error,
              reference.value, reference.error);
}

std::string degrees(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// The catalogue's later models: Ashikhmin–Shirley and Schlick 1994 anisotropic, Schlick's
/// rational Phong and Kajiya's fibres not reciprocal (g integrates f over its first argument).
/// Their reference cuts at the models' mass hints as well: the last two fall to 0 across the
/// kGrazingCosFloor layer at the horizon (1/max(k·n, 1e-6)), which a reference without that cut
/// integrates as if f went on to the horizon (kajiya h at theta_j 80: 5.7e-7 too high).
reference::Options later_reference_options() {
  reference::Options options;
  options.tolerance = kReferenceTol;
  return options;
}

const std::vector<std::string>& catalogue_models() {
  static const std::vector<std::string> specs{"ashikhmin-shirley:rd=0.5,rs=0.05,nu=20,nv=200",
                                              "schlick:c=0.5,r=0.1,p=0.3", "schlick-phong:kd=0.5,ks=0.5,n=20",
                                              "kajiya:kd=0.3,ks=0.7,n=20"};
  return specs;
}

/// The engine's g or h of each model at the given geometries (theta_i, theta_j, phi in degrees;
/// for h theta_i is unused) against the reference; returns the dishonest cases.
std::set<std::string> dishonest_cases(Law law, const std::vector<std::array<double, 3>>& geometries,
                                      const std::vector<std::string>& specs = models(),
                                      const reference::Options& reference_options = pinned_reference_options()) {
  CubatureOptions options;
  options.abs_tol = kEngineTol;
  std::set<std::string> dishonest;
  for (const std::string& spec : specs) {
    const ModelPtr model = parse_model(spec);
    for (const auto& [theta_i, theta_j, phi] : geometries) {
      const Vec3 j = direction(theta_j * pi / 180, phi * pi / 180);
      if (law == Law::g) {
        const Vec3 i = direction(theta_i * pi / 180, 0.0);
        check_agreement(
            spec + " g at theta_i " + degrees(theta_i) + ", theta_j " + degrees(theta_j) + ", phi " + degrees(phi),
            vignetting(*model, i, j, options), reference::vignetting(*model, i, j, reference_options), dishonest);
      } else {
        check_agreement(spec + " h at theta_j " + degrees(theta_j), darkening(*model, j, options),
                        reference::darkening(*model, j, reference_options), dishonest);
      }
    }
  }
  return dishonest;
}

TEST(IndependentReference, VignettingOfEveryLobeFamily) {
  std::vector<std::array<double, 3>> geometries;
  for (double theta_i : {35.0, 120.0})
    for (double theta_j : {20.0, 70.0})
      for (double phi : {0.0, 180.0}) geometries.push_back({theta_i, theta_j, phi});
  EXPECT_EQ(dishonest_cases(Law::g, geometries), kKnownDishonest);
}

TEST(IndependentReference, DarkeningOfEveryLobeFamily) {
  const double azimuth = 0.5 * 180 / pi;  // radians 0.5: off every plane of symmetry
  EXPECT_TRUE(dishonest_cases(Law::h, {{0, 0, azimuth}, {0, 45, azimuth}, {0, 80, azimuth}}).empty());
}

/// The later models' cases where the engine (tolerance 1e-8) and this reference disagree by more
/// than both estimates: 2e-8 to 9e-8, listed, not hidden; the test fails if the list changes either
/// way. Ashikhmin-shirley's f has a kink where i·n = j·n, max(i·n, j·n), that neither
/// cuts at. With the null-rule estimate (integrate/cubature.h) and kajiya's kGrazingLayer,
/// ashikhmin-shirley's g at (35, 70, 180), schlick-phong's at (35, 20, 0), two of kajiya's g and
/// its h at 45 left the lists. The ladder of longitudes from a horizon layer beside a lobe at a
/// coordinate pole (integrate/laws_integrals.cpp) mended kajiya's h at j = n and its grazing cases of
/// the extremes grid, and moved the panels that kajiya's kink curve crosses at three of these g
/// (added below, 1.4-2.8x their estimates): a kink across a panel is what the estimate is weakest on.
const std::set<std::string> kLaterDisagreeG{
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 35, theta_j 20, phi 0",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 35, theta_j 20, phi 180",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 35, theta_j 20, phi 250",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 120, theta_j 20, phi 0",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 35, theta_j 70, phi 250",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 120, theta_j 20, phi 180",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 120, theta_j 20, phi 250",
    "kajiya:kd=0.3,ks=0.7,n=20 g at theta_i 120, theta_j 70, phi 250",
};
const std::set<std::string> kLaterDisagreeH{
    "ashikhmin-shirley:rd=0.5,rs=0.05,nu=20,nv=200 h at theta_j 80",
    "schlick:c=0.5,r=0.1,p=0.3 h at theta_j 80",
};

/// The later models at the same geometries and at an azimuth off every plane of symmetry, where
/// the anisotropic lobes (exponents or facets along x) differ from their mirror images.
TEST(IndependentReference, VignettingAndDarkeningOfTheLaterModels) {
  std::vector<std::array<double, 3>> geometries;
  for (double theta_i : {35.0, 120.0})
    for (double theta_j : {20.0, 70.0})
      for (double phi : {0.0, 180.0, 250.0}) geometries.push_back({theta_i, theta_j, phi});
  EXPECT_EQ(dishonest_cases(Law::g, geometries, catalogue_models(), later_reference_options()), kLaterDisagreeG);
  const double azimuth = 0.5 * 180 / pi;
  EXPECT_EQ(dishonest_cases(Law::h, {{0, 0, azimuth}, {0, 45, azimuth}, {0, 80, azimuth}}, catalogue_models(),
                            later_reference_options()),
            kLaterDisagreeH);
}

/// The extremes grid's budget per case (kExtremesReferenceBudget, reports/extremes.h).
constexpr long long kGridBudget = 5'000'000;
/// Rounding on top of the reference's estimate: it sums ~10^4 panel values (reports/extremes.cpp).
constexpr double kRounding = 1e-13;

/// A view just above the horizon puts the specular lobe of h on the lune coordinates' pole; the
/// inner integrals at the other pole are ~1e-90 and all cancellation noise, and each was bisected
/// to full depth against its own size (59 million evaluations at j·n = 1e-6: "0 ± inf" in
/// docs/reliability-extremes.md). By reciprocity h(j) = a(j), K&P's printed a_s for alpha = 8, which
/// docs/errata.md finds exact.
TEST(IndependentReference, GrazingViewResolvesWithinTheGridsBudget) {
  const ModelPtr model = parse_model("specular:alpha=8");
  reference::Options options;
  options.max_evaluations = kGridBudget;
  for (const double cos_j : {1e-6, 1e-9}) {
    const reference::Value h = reference::darkening(*model, direction_from_cos(cos_j), options);
    ASSERT_TRUE(h.resolved) << cos_j << ": " << h.evaluations << " evaluations";
    EXPECT_NEAR(h.value, specular::a_alpha8_printed(cos_j), h.total_error() + kRounding) << cos_j;
  }
}

/// The antipode reference's coordinates (polar about -j, each ray cut where it enters and leaves
/// the lune) on Lambert's law, whose g is rho (1 + i·n)/2 whatever j (K&P): the whole lune, a sliver
/// with its pole 2.6° above the nadir, a sky on the horizon, with views at the zenith, at 45° and
/// 1e-9 above the horizon (the antipode 1e-9 below it), and the albedo 1.
TEST(IndependentReference, AntipodeCoordinatesGiveLambertsClosedForm) {
  const ModelPtr model = parse_model("lambert");
  reference::Options options;
  options.about_antipode = true;
  options.absolute_tolerance = 1e-11;
  options.max_evaluations = kGridBudget;
  for (const double cos_i : {1.0, 0.3, 0.0, -0.999})
    for (const double cos_j : {1.0, 0.7071, 1e-9})
      for (const double phi : {0.0, 2.0, pi}) {
        const reference::Value g =
            reference::vignetting(*model, direction_from_cos(cos_i), direction_from_cos(cos_j, phi), options);
        ASSERT_TRUE(g.resolved) << cos_i << " " << cos_j << " " << phi;
        EXPECT_NEAR(g.value, (1.0 + cos_i) / 2, g.total_error() + kRounding)
            << "i·n " << cos_i << ", j·n " << cos_j << ", phi " << phi;
      }
  for (const double cos_i : {1.0, 1e-9}) {
    const reference::Value a = reference::albedo(*model, direction_from_cos(cos_i, 1.0), options);
    ASSERT_TRUE(a.resolved) << cos_i;
    EXPECT_NEAR(a.value, 1.0, a.total_error() + kRounding) << cos_i;
  }
}

}  // namespace
}  // namespace ganzfeld
