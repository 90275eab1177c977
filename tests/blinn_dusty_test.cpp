// Blinn 1982 dusty/cloud layer (models/blinn_dusty.h): phase-function normalization and sign
// convention, known limits (thick layer = Lommel–Seeliger form, thin layer, tau = 0), Blinn's
// printed brightness, horizon behaviour, reciprocity and isotropy, energy by the engine
// (integrate/laws.h) against the single-scattering bound and a closed form, mixtures, mass
// hints, and parameter validation through the registry path.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "tests/test_support.h"

#include "integrate/laws.h"
#include "models/blinn_dusty.h"
#include "models/classic_models.h"
#include "models/mixture.h"
#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

// --- tolerances --------------------------------------------------------------------------------
/// 1-D adaptive Gauss–Kronrod (61 points, tolerance 1e-12 requested) of a smooth or |g| <= 0.99
/// peaked phase function: the normalization integrals are good to ~1e-12; allow 1e-9.
constexpr double kPhaseIntegralTol = 1e-9;
using testing_support::kAlbedoTol;
/// Relative rounding of a closed-form evaluation chain (a dozen operations, one expm1, one pow).
constexpr double kFormulaRel = 1e-13;
/// Rotating i and j about n changes the inputs by ~1 ulp; the sharpest HG lobe (g = 0.99,
/// d ln Phi/d cos alpha = 3g/(1 - g)^2 ~ 3e4) amplifies that to ~1e-11 relative: allow 1e-9.
constexpr double kRotationRel = 1e-9;
/// At the exact zero of 1 + x cos alpha (x = 1, j = -i on the horizon) a rotation about n moves
/// i + j by an ulp: f ~ 1e-27 either way, rounding noise compared absolutely (f is O(0.1) 1/sr).
constexpr double kValueFloor = 1e-12;
/// Thin-layer expansion 1 - exp(-x) = x (1 - x/2 + ...): with x = tau (1/mu_i + 1/mu_j) <= 2e-5
/// below, the relative difference from x is <= 1e-5; allow 2e-5.
constexpr double kThinLayerRel = 2e-5;

CubatureOptions options() { return testing_support::cubature_options(testing_support::kAlbedoCubatureTol); }
using testing_support::albedo_at;
using testing_support::kIncidenceCosines;

// --- the registry path -------------------------------------------------------------------------
const ModelInfo& info() {
  static const std::vector<ModelInfo> catalogue = [] {
    std::vector<ModelInfo> c;
    register_blinn_dusty_models(c);
    return c;
  }();
  return catalogue.at(0);
}

/// blinn-dusty with `given` parameters (validated), the rest at their defaults.
ModelPtr make(const ParamValues& given = {}) { return make_model(ModelSpec{"blinn-dusty", given}); }

/// The parameters of a canonical spec of this model (round-trip check).
ParamValues params_of_spec(const std::string& spec) { return parse_spec(spec).terms.front().model.values; }

// A spread of materials: every phase function, extreme parameters, thin and thick layers.
const std::vector<ParamValues> kMaterials{
    {},
    {{"phase", 0}, {"w", 1}, {"tau", 1000}},
    {{"phase", 0}, {"w", 0.3}, {"tau", 1e-4}},
    {{"phase", 1}, {"x", 1}, {"w", 1}, {"tau", 5}},
    {{"phase", 1}, {"x", -1}, {"w", 1}, {"tau", 1000}},
    {{"phase", 2}, {"w", 1}, {"tau", 1000}},
    {{"phase", 2}, {"w", 0.8}, {"tau", 0.5}},
    {{"phase", 3}, {"w", 1}, {"tau", 1000}},
    {{"phase", 4}, {"g", 0.99}, {"w", 1}, {"tau", 1000}},
    {{"phase", 4}, {"g", -0.99}, {"w", 1}, {"tau", 1000}},
    {{"phase", 4}, {"g", 0.325}, {"w", 1}, {"tau", 2}},
    {{"phase", 5}, {"w", 1}, {"tau", 1000}},
    {{"phase", 5}, {"g", 0.99}, {"g2", -0.99}, {"m", 0.5}, {"w", 1}, {"tau", 0.1}},
};

std::string describe(const ParamValues& p) { return make(p)->spec(); }

std::vector<Vec3> test_directions() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> dirs;
  for (double c : {0.0, 1e-12, 1e-6, 1e-3, 0.2, 0.5, 0.9, 1.0 - 1e-12, 1.0})
    for (double phi : {0.0, 0.5 * pi, pi, 1.5 * pi}) dirs.push_back(direction_from_cos(c, phi));
  for (int k = 0; k < 40; ++k) dirs.push_back(direction_from_cos(u(rng), 2 * pi * u(rng)));
  return dirs;
}

Vec3 rotate_z(const Vec3& v, double a) {
  return {std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z};
}

/// The phase function of a material, as a function of the phase angle.
double phi_at(const BlinnPhaseFunction& phase, double alpha) { return phase(PhaseAngle::of(alpha)); }

/// (1/4pi) ∫ Phi(alpha) h(alpha) dOmega = (1/2) ∫_0^pi Phi h sin alpha d alpha.
template <class H>
double sphere_mean(const BlinnPhaseFunction& phase, H h) {
  // Split at alpha = 0.3: the sharpest allowed HG lobes (width ~0.01 at alpha = 0 or pi) then
  // sit at the ends of panels, where Gauss–Kronrod resolves them.
  const auto integrand = [&](double alpha) { return 0.5 * phi_at(phase, alpha) * h(alpha) * std::sin(alpha); };
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  double total = 0.0;
  const double cuts[] = {0.0, 0.3, pi - 0.3, pi};
  for (int k = 0; k < 3; ++k) total += GK::integrate(integrand, cuts[k], cuts[k + 1], 15, 1e-12);
  return total;
}

// --- catalogue and validation ------------------------------------------------------------------
TEST(BlinnDusty, RegisteredWithADocumentedParameterTable) {
  const ModelInfo& m = info();
  EXPECT_EQ(m.name, "blinn-dusty");
  EXPECT_FALSE(m.summary.empty());
  EXPECT_FALSE(m.source.empty());
  EXPECT_TRUE(m.closed_forms.empty());
  for (const auto& p : m.parameters) {
    EXPECT_FALSE(p.meaning.empty()) << p.name;
    EXPECT_LE(p.min, p.default_value) << p.name;
    EXPECT_LE(p.default_value, p.max) << p.name;
  }
  const ModelPtr d = make();
  EXPECT_EQ(d->spec(), "blinn-dusty:w=0.5,tau=1,phase=0,x=0.5,g=0.5,g2=-0.5,m=0.596");
  for (const auto& p : kMaterials) {
    const ModelPtr model = make(p);
    EXPECT_EQ(make(params_of_spec(model->spec()))->spec(), model->spec());  // canonical spec round-trips
    EXPECT_EQ(model->traits().reciprocal, m.traits.reciprocal);
    EXPECT_EQ(model->traits().isotropic, m.traits.isotropic);
    EXPECT_EQ(model->traits().energy, m.traits.energy);
  }
}

TEST(BlinnDusty, OutOfRangeParametersThrowInputError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<ParamValues> bad{{{"w", -0.1}},   {{"w", 1.5}},   {{"tau", -1}},    {{"tau", 1e4}},
                                     {{"phase", -1}}, {{"phase", 6}}, {{"phase", 2.5}}, {{"x", 1.5}},
                                     {{"x", -1.01}},  {{"g", 1}},     {{"g", -0.995}},  {{"g2", 0.999}},
                                     {{"m", 2}},      {{"m", -0.5}},  {{"w", nan}},     {{"tau", INFINITY}}};
  for (const auto& p : bad) EXPECT_THROW(make(p), InputError) << p.begin()->first << "=" << p.begin()->second;
  // the message names model, key, value and the allowed range
  try {
    make({{"g", 1}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "blinn-dusty: g=1 is out of range; allowed: a real number in [-0.99, 0.99]");
  }
  for (double ok : {0.0, 1.0}) EXPECT_NO_THROW(make({{"w", ok}}));
  for (double ok : {0.0, 1000.0}) EXPECT_NO_THROW(make({{"tau", ok}}));
  for (double ok : {0.0, 1.0, 2.0, 3.0, 4.0, 5.0}) EXPECT_NO_THROW(make({{"phase", ok}}));
}

// --- phase functions ---------------------------------------------------------------------------
std::vector<BlinnPhaseFunction> all_phases() {
  using K = BlinnPhase;
  std::vector<BlinnPhaseFunction> v{{K::constant}, {K::lambert_sphere}, {K::rayleigh}};
  for (double x : {-1.0, -0.3, 0.0, 0.5, 1.0}) v.push_back({K::anisotropic, x});
  for (double g : {-0.99, -0.9, -0.5, 0.0, 0.325, 0.5, 0.9, 0.99}) v.push_back({K::henyey_greenstein, 0, g});
  v.push_back({K::two_term_hg, 0, 0.5, -0.5, 0.596});
  v.push_back({K::two_term_hg, 0, 0.99, -0.99, 0.3});
  return v;
}

TEST(BlinnDusty, EveryPhaseFunctionIsNormalizedOverTheSphere) {
  // Blinn's normalization (1/4pi) ∫ Phi dOmega = 1.
  for (const auto& phase : all_phases()) {
    const double mean = sphere_mean(phase, [](double) { return 1.0; });
    EXPECT_NEAR(mean, 1.0, kPhaseIntegralTol) << static_cast<int>(phase.kind) << " x=" << phase.x << " g=" << phase.g;
    for (double alpha = 0.0; alpha <= pi; alpha += pi / 64) EXPECT_GE(phi_at(phase, alpha), 0.0);
  }
}

TEST(BlinnDusty, KnownPhaseValues) {
  using K = BlinnPhase;
  const BlinnPhaseFunction lambert{K::lambert_sphere}, rayleigh{K::rayleigh};
  EXPECT_NEAR(phi_at(lambert, 0.0), 8.0 / 3.0, kFormulaRel);  // full phase: 8/(3pi) * pi
  EXPECT_NEAR(phi_at(lambert, pi / 2), 8.0 / (3.0 * pi), kFormulaRel);
  EXPECT_NEAR(phi_at(lambert, pi), 0.0, kFormulaRel);  // the sphere's dark side
  EXPECT_DOUBLE_EQ(phi_at(rayleigh, 0.0), 1.5);
  EXPECT_DOUBLE_EQ(phi_at(rayleigh, pi / 2), 0.75);
  // HG at its peak (1 + g)/(1 - g)^2 and at the antipode (1 - g)/(1 + g)^2
  EXPECT_NEAR(henyey_greenstein(0.5, PhaseAngle::of(0.0)), 6.0, kFormulaRel);
  EXPECT_NEAR(henyey_greenstein(0.5, PhaseAngle::of(pi)), 2.0 / 9.0, kFormulaRel);
  // |g| = 1 is a delta, outside the model's range: 0, never NaN
  EXPECT_EQ(henyey_greenstein(1.0, PhaseAngle::of(0.0)), 0.0);
}

TEST(BlinnDusty, HenyeyGreensteinWithGZeroIsTheConstantPhase) {
  using K = BlinnPhase;
  for (double alpha = 0.0; alpha <= pi; alpha += pi / 32) {
    EXPECT_EQ(phi_at({K::henyey_greenstein, 0, 0.0}, alpha), 1.0);
    EXPECT_EQ(phi_at({K::two_term_hg, 0, 0.0, 0.0, 0.3}, alpha), 1.0);
    EXPECT_EQ(phi_at({K::anisotropic, 0.0}, alpha), 1.0);
  }
  const Vec3 i = direction_from_cos(0.6, 0.2);
  const ModelPtr hg0 = make({{"phase", 4}, {"g", 0}}), constant = make({{"phase", 0}});
  for (const Vec3& j : test_directions()) EXPECT_EQ(hg0->f(i, j), constant->f(i, j));
}

TEST(BlinnDusty, RayleighIsSymmetricForwardAndBack) {
  const BlinnPhaseFunction rayleigh{BlinnPhase::rayleigh};
  for (double alpha = 0.0; alpha <= pi / 2; alpha += pi / 40)
    EXPECT_NEAR(phi_at(rayleigh, alpha), phi_at(rayleigh, pi - alpha), kFormulaRel);
  // In the BRDF: two views at the same elevation with opposite cos alpha (mu_i = mu_j = 0.2:
  // i·j = 0.04 + 0.96 cos dphi = ±0.52) give the same f.
  const ModelPtr m = make({{"phase", 3}, {"tau", 3}});
  const Vec3 i = direction_from_cos(0.2, 0.0);
  const Vec3 j1 = direction_from_cos(0.2, std::acos(0.5)), j2 = direction_from_cos(0.2, std::acos(-0.56 / 0.96));
  ASSERT_NEAR(glm::dot(i, j1), -glm::dot(i, j2), 1e-15);
  EXPECT_NEAR(m->f(i, j1), m->f(i, j2), kFormulaRel * m->f(i, j1));
}

TEST(BlinnDusty, SignConventionGPositiveScattersBackToTheSource) {
  using K = BlinnPhase;
  // <cos alpha> = g with alpha the phase angle (cos alpha = i·j): g > 0 returns light towards the
  // source; the radiative-transfer asymmetry <cos(pi - alpha)> is -g. Likewise <cos alpha> = x/3.
  for (double g : {-0.9, -0.5, 0.325, 0.9}) {
    const double mean_cos = sphere_mean({K::henyey_greenstein, 0, g}, [](double a) { return std::cos(a); });
    EXPECT_NEAR(mean_cos, g, kPhaseIntegralTol) << g;
  }
  EXPECT_NEAR(sphere_mean({K::anisotropic, 0.6}, [](double a) { return std::cos(a); }), 0.2, kPhaseIntegralTol);
  // The brightest view: g > 0 at the source direction itself; g < 0 along the forward horizon
  // (the peak -i lies below the surface). Scan the hemisphere for i at 60 degrees from n.
  const Vec3 i = direction_from_cos(0.5, 0.0);
  const auto brightest = [&](const ModelPtr& m) {
    Vec3 best{0, 0, 1};
    double f_best = -1.0;
    for (int a = 0; a <= 400; ++a)
      for (int b = 0; b < 400; ++b) {
        const Vec3 j = direction_from_cos(a / 400.0, 2 * pi * b / 400.0);
        if (const double f = m->f(i, j); f > f_best) f_best = f, best = j;
      }
    return best;
  };
  const Vec3 back = brightest(make({{"phase", 4}, {"g", 0.9}, {"tau", 1000}}));
  EXPECT_GT(glm::dot(back, i), std::cos(0.02));  // within the 400x400 scan's resolution
  const Vec3 fwd = brightest(make({{"phase", 4}, {"g", -0.9}, {"tau", 1000}}));
  EXPECT_LT(fwd.x, -0.99);  // away from the source's azimuth (i.x > 0) ...
  EXPECT_LT(fwd.z, 0.05);   // ... and grazing
  // Lambertian spheres backscatter like the Moon: brighter towards the source than the mirror.
  const ModelPtr lambert = make({{"phase", 2}, {"tau", 1000}});
  EXPECT_GT(lambert->f(i, i), 3.0 * lambert->f(i, mirror(i)));
}

// --- the BRDF: limits and Blinn's brightness ---------------------------------------------------
TEST(BlinnDusty, FIsBlinnsBrightnessOver4PiMu0) {
  // Blinn's printed B = w Phi mu0/(mu + mu0) [1 - exp(-tau(1/mu + 1/mu0))], B = 4pi mu_0 f.
  for (const auto& p : kMaterials) {
    const auto m = std::dynamic_pointer_cast<const BlinnDusty>(make(p));
    const double w = p.count("w") ? p.at("w") : 0.5;
    const double tau = p.count("tau") ? p.at("tau") : 1.0;
    for (double mu0 : {0.05, 0.4, 1.0})
      for (double mu : {0.1, 0.7, 1.0}) {
        const Vec3 i = direction_from_cos(mu0, 0.0), j = direction_from_cos(mu, 2.0);
        const double B = w * m->phase()(PhaseAngle::between(i, j)) * mu0 / (mu + mu0) *
                         (1.0 - std::exp(-tau * (1.0 / mu + 1.0 / mu0)));
        EXPECT_NEAR(4.0 * pi * mu0 * m->f(i, j), B, kFormulaRel * (1.0 + B)) << describe(p);
      }
  }
}

TEST(BlinnDusty, ThickThinAndEmptyLayers) {
  const auto dirs = test_directions();
  for (int phase = 0; phase <= 5; ++phase) {
    const auto thick = std::dynamic_pointer_cast<const BlinnDusty>(make({{"phase", phase}, {"w", 0.7}, {"tau", 1000}}));
    const auto thin = std::dynamic_pointer_cast<const BlinnDusty>(make({{"phase", phase}, {"w", 0.7}, {"tau", 1e-6}}));
    const ModelPtr empty = make({{"phase", phase}, {"tau", 0}});
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        EXPECT_EQ(empty->f(i, j), 0.0);
        if (!(i.z > 0.0 && j.z > 0.0)) continue;
        const double Phi = thick->phase()(PhaseAngle::between(i, j));
        // tau -> inf: the Lommel–Seeliger form w Phi/(4pi (mu_i + mu_j)) (exp(-2000) = 0)
        const double ls = 0.7 * Phi / (4 * pi * std::max(i.z + j.z, kGrazingCosFloor));
        EXPECT_NEAR(thick->f(i, j), ls, kFormulaRel * ls) << "phase " << phase;
        // tau -> 0: single scattering in an optically thin layer, w Phi tau/(4pi mu_i mu_j), while
        // tau (1/mu_i + 1/mu_j) << 1 (here <= 2e-5: cosines >= 0.1)
        if (i.z >= 0.1 && j.z >= 0.1) {
          const double thin_limit = 0.7 * Phi * 1e-6 / (4 * pi * i.z * j.z);
          EXPECT_NEAR(thin->f(i, j), thin_limit, kThinLayerRel * thin_limit) << "phase " << phase;
        }
      }
  }
}

TEST(BlinnDusty, FiniteNonNegativeZeroBelowAndTheHorizonLimit) {
  const auto dirs = test_directions();
  for (const auto& p : kMaterials) {
    const ModelPtr m = make(p);
    testing_support::expect_finite_non_negative(*m, dirs, describe(p));
    // one direction on the horizon: 1 - exp(-inf) = 1, f = w Phi/(4pi mu_other), the formula's limit
    const auto b = std::dynamic_pointer_cast<const BlinnDusty>(m);
    const Vec3 h{1, 0, 0};
    for (double mu : {1e-3, 0.5, 1.0}) {
      const Vec3 j = direction_from_cos(mu, 2.5);
      const double w = p.count("w") ? p.at("w") : 0.5;
      const double expected = w * b->phase()(PhaseAngle::between(h, j)) / (4 * pi * mu);
      EXPECT_NEAR(m->f(h, j), expected, kFormulaRel * expected) << describe(p);
      EXPECT_NEAR(m->f(h, direction_from_cos(mu * (1 + 1e-9), 2.5)), expected, 1e-8 * expected);  // continuous
    }
    // both on the horizon: finite (mu_i + mu_j floored at kGrazingCosFloor)
    EXPECT_TRUE(std::isfinite(m->f(h, h)));
    EXPECT_TRUE(std::isfinite(m->f(h, Vec3{-1, 0, 0})));
  }
}

TEST(BlinnDusty, ReciprocalBitExactAndIsotropic) {
  const auto dirs = test_directions();
  for (const auto& p : kMaterials) {
    const ModelPtr m = make(p);
    for (const Vec3& i : dirs)
      for (const Vec3& j : dirs) {
        ASSERT_EQ(m->f(i, j), m->f(j, i)) << describe(p);
        const double f = m->f(i, j), fr = m->f(rotate_z(i, 1.1), rotate_z(j, 1.1));
        ASSERT_NEAR(fr, f, kRotationRel * f + kValueFloor) << describe(p);
      }
  }
}

// --- energy by the engine ----------------------------------------------------------------------

TEST(BlinnDusty, AlbedoIsBelowTheSingleScatteringBound) {
  // Of the beam, 1 - exp(-tau/mu_i) is intercepted, w of that re-emitted, and only part of it
  // escapes upwards unscattered: a(i) <= w (1 - exp(-tau/mu_i)) <= w <= 1 (plausible).
  for (const auto& p : kMaterials) {
    const ModelPtr m = make(p);
    const double w = p.count("w") ? p.at("w") : 0.5, tau = p.count("tau") ? p.at("tau") : 1.0;
    for (double c : kIncidenceCosines) {
      const double a = albedo_at(*m, c);
      EXPECT_GE(a, -kAlbedoTol) << describe(p) << " cos_i=" << c;
      EXPECT_LE(a, w * -std::expm1(-tau / c) + kAlbedoTol) << describe(p) << " cos_i=" << c;
    }
  }
}

TEST(BlinnDusty, IsotropicThickLayerAlbedoClosedForm) {
  // Phi = 1, tau = inf: a(mu_0) = (w/2) ∫_0^1 mu/(mu + mu_0) d mu = (w/2) (1 - mu_0 ln(1 + 1/mu_0)).
  const ModelPtr m = make({{"phase", 0}, {"w", 1}, {"tau", 1000}});
  for (double c : kIncidenceCosines) {
    const double closed = 0.5 * (1.0 - c * std::log1p(1.0 / c));
    EXPECT_NEAR(albedo_at(*m, c), closed, kAlbedoTol) << "cos_i=" << c;
  }
}

TEST(BlinnDusty, FiniteLayerAlbedoMatchesOneDimensionalQuadrature) {
  // Phi = 1: a(mu_0) = (w/2) ∫_0^1 mu/(mu + mu_0) (1 - exp(-tau (1/mu + 1/mu_0))) d mu.
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  for (double tau : {0.01, 0.3, 2.0}) {
    const ModelPtr m = make({{"phase", 0}, {"w", 0.9}, {"tau", tau}});
    for (double c : {1.0, 0.5, 0.1, 0.01}) {
      const auto integrand = [&](double mu) {
        return mu > 0.0 ? mu / (mu + c) * -std::expm1(-tau * (1.0 / mu + 1.0 / c)) : 0.0;
      };
      const double ref = 0.45 * (GK::integrate(integrand, 0.0, std::min(tau, 0.5), 15, 1e-12) +
                                 GK::integrate(integrand, std::min(tau, 0.5), 1.0, 15, 1e-12));
      EXPECT_NEAR(albedo_at(*m, c), ref, kAlbedoTol) << "tau=" << tau << " cos_i=" << c;
    }
  }
}

TEST(BlinnDusty, DarkeningEqualsAlbedo) {
  // Reciprocal model: h(j) = ∫ (k·n) f(k, j) dk = a(j).
  for (const auto& p : kMaterials) {
    const ModelPtr m = make(p);
    for (double c : {1.0, 0.5, 0.1, 1e-3}) {
      const Vec3 d = direction_from_cos(c, 0.3);
      const Estimate a = albedo(*m, d, options()), h = darkening(*m, d, options());
      ASSERT_TRUE(a.converged && h.converged) << describe(p);
      EXPECT_NEAR(h.value, a.value, 2 * kAlbedoTol) << describe(p) << " cos=" << c;
    }
  }
}

// --- mixtures ----------------------------------------------------------------------------------
TEST(BlinnDusty, MixturesOfPhaseFunctionsAreSpecMixtures) {
  // f is linear in Phi: for equal w and tau, the partitive mixture 0.3*A + 0.7*B of two
  // blinn-dusty lobes is the layer with the phase function 0.3 Phi_A + 0.7 Phi_B; and phase 5
  // is the mixture m HG(g) + (1 - m) HG(g2).
  const ParamValues base{{"w", 0.8}, {"tau", 2}};
  const auto with = [&](ParamValues extra) {
    for (const auto& kv : base) extra.insert(kv);
    return make(extra);
  };
  const auto lambert = std::dynamic_pointer_cast<const BlinnDusty>(with({{"phase", 2}}));
  const Mixture mix({{0.3, lambert}, {0.7, with({{"phase", 3}})}});
  const ModelPtr two = with({{"phase", 5}, {"g", 0.8}, {"g2", -0.3}, {"m", 0.25}});
  const Mixture hg_mix({{0.25, with({{"phase", 4}, {"g", 0.8}})}, {0.75, with({{"phase", 4}, {"g", -0.3}})}});
  const BlinnPhaseFunction rayleigh{BlinnPhase::rayleigh};
  for (const Vec3& i : test_directions())
    for (const Vec3& j : test_directions()) {
      if (!(i.z > 1e-3 && j.z > 1e-3)) continue;  // away from the floored horizon
      const PhaseAngle a = PhaseAngle::between(i, j);
      const double ratio = (0.3 * lambert->phase()(a) + 0.7 * rayleigh(a)) / lambert->phase()(a);
      if (std::isfinite(ratio)) { EXPECT_NEAR(mix.f(i, j), lambert->f(i, j) * ratio, 1e-12 * mix.f(i, j)); }
      EXPECT_NEAR(two->f(i, j), hg_mix.f(i, j), 1e-12 * two->f(i, j));
    }
}

// --- mass hints --------------------------------------------------------------------------------
TEST(BlinnDusty, MassHintsPointAtTheHenyeyGreensteinLobes) {
  const Vec3 fixed = direction_from_cos(0.05, 0.7);
  const MassHints back = make({{"phase", 4}, {"g", 0.99}, {"tau", 1000}})->mass_hints(fixed, Varying::outgoing);
  ASSERT_EQ(back.peaks.size(), 1u);
  EXPECT_EQ(back.peaks[0].direction, fixed);
  EXPECT_NEAR(back.peaks[0].width, 0.01 / std::sqrt(0.99), 1e-15);
  EXPECT_DOUBLE_EQ(back.horizon_layer, 0.05);  // the Lommel–Seeliger switch at mu ~ mu_fixed
  const MassHints fwd = make({{"phase", 4}, {"g", -0.9}})->mass_hints(fixed, Varying::incident);
  ASSERT_EQ(fwd.peaks.size(), 1u);
  EXPECT_EQ(fwd.peaks[0].direction, -fixed);
  const MassHints two = make({{"phase", 5}})->mass_hints(fixed, Varying::outgoing);
  EXPECT_EQ(two.peaks.size(), 2u);
  EXPECT_TRUE(make({{"phase", 2}})->mass_hints(fixed, Varying::outgoing).peaks.empty());
  EXPECT_DOUBLE_EQ(make({{"tau", 0.01}})->mass_hints(Vec3{0, 0, 1}, Varying::outgoing).horizon_layer, 0.01);
}

}  // namespace
}  // namespace ganzfeld
