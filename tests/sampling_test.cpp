// Importance sampling (Model::sample_incident / pdf_incident; Edwards et al. eq. 12-13, 21, 25,
// 28-29 for the halfway-vector-disk models, Heitz 2018's visible normals for ggx, the papers'
// halfway-vector draws for ashikhmin-shirley and schlick, cosine sampling by default).
//
// 1. Chi-square goodness of fit, in the style of pbrt-v4's bsdfs_test.cpp: draw N directions,
//    histogram them on a (theta, phi) grid of the hemisphere, and compare with the expected
//    counts N ∫_bin pdf dω. The expected counts come from our adaptive cubature per bin (with
//    cut lines at the model's lobe hints), and their sum is checked against the success
//    probability first, so a bin integral that missed a lobe cannot pass silently. Bins with
//    expected counts below 5 are pooled; failed draws form their own bin. Deterministic seeds;
//    the test rejects at significance 1e-3 per case (there are ~50 cases).
// 2. Sample weights: for the HVD models f (i·n)/pdf is the constant (1 − F) C_d + F for every draw
//    (perfect importance sampling of the law of darkening), up to 89.99 deg.
// 3. Unbiasedness: the mean weight of any model's sampler estimates h(j); it must agree with the
//    cubature within 5 standard errors.
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <boost/math/distributions/chi_squared.hpp>

#include "integrate/cubature.h"
#include "integrate/laws.h"
#include "models/hvd.h"
#include "models/spec.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

constexpr int kThetaBins = 32, kPhiBins = 64;
constexpr double kSignificance = 1e-3;

Vec3 outgoing(double theta_deg, double phi_deg) {
  const double t = theta_deg * pi / 180.0, p = phi_deg * pi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

/// Expected probability per (theta, phi) bin: ∫ pdf sin(theta) dtheta dphi, with initial cuts at
/// the lobe hints that fall into the bin (centre and ± 1, 4 widths, in both coordinates).
std::vector<double> bin_probabilities(const Model& model, const Vec3& j, double& error) {
  std::vector<double> theta_lines, phi_lines;
  for (const Peak& peak : model.mass_hints(j, Varying::incident).peaks) {
    const Vec3 d = glm::normalize(peak.direction);
    const double theta_d = std::acos(std::clamp(d.z, -1.0, 1.0));
    double phi_d = std::atan2(d.y, d.x);
    if (phi_d < 0.0) phi_d += 2.0 * pi;
    for (double w : {peak.width, peak.across > 0.0 ? peak.across : peak.width})
      for (double m : {-4.0, -1.0, 0.0, 1.0, 4.0}) {
        theta_lines.push_back(theta_d + m * w);
        phi_lines.push_back(phi_d + m * w / std::max(std::sin(theta_d), 1e-3));
      }
  }
  std::vector<double> p(kThetaBins * kPhiBins);
  error = 0.0;
  CubatureOptions options;
  options.abs_tol = 1e-11;
  for (int a = 0; a < kThetaBins; ++a)
    for (int b = 0; b < kPhiBins; ++b) {
      const double t0 = 0.5 * pi * a / kThetaBins, t1 = 0.5 * pi * (a + 1) / kThetaBins;
      const double p0 = 2.0 * pi * b / kPhiBins, p1 = 2.0 * pi * (b + 1) / kPhiBins;
      std::vector<double> tc{t0, t1}, pc{p0, p1};
      for (double t : theta_lines)
        if (t > t0 && t < t1) tc.push_back(t);
      for (double q : phi_lines)
        if (q > p0 && q < p1) pc.push_back(q);
      const double scale = 1e-3 * std::min(t1 - t0, p1 - p0);
      const auto integrand = pointwise<2>([&](double t, double q) {
        const Vec3 i{std::sin(t) * std::cos(q), std::sin(t) * std::sin(q), std::cos(t)};
        return model.pdf_incident(j, i) * std::sin(t);
      });
      const Estimate e = adaptive_cubature<2>(
          integrand, {tidy_cuts(tc, t0, t1, 1e-3 * scale), tidy_cuts(pc, p0, p1, 1e-3 * scale)}, options);
      p[a * kPhiBins + b] = e.value;
      error += e.error;
    }
  return p;
}

struct ChiSquare {
  double p_value = 0.0, expected_total = 0.0, observed_success = 0.0;
  int dof = 0;
};

ChiSquare chi_square(const Model& model, const Vec3& j, int samples, unsigned seed, double success_probability) {
  double integration_error = 0.0;
  const std::vector<double> expected = bin_probabilities(model, j, integration_error);
  ChiSquare out;
  for (double e : expected) out.expected_total += e;
  // The bin integrals must account for the whole probability of a successful draw.
  // (success_probability < 0: not known in closed form, e.g. Ward lobe draws reflected below
  // the horizon; the failure bin then carries 1 - the sum.)
  if (success_probability >= 0.0) {
    EXPECT_NEAR(out.expected_total, success_probability, 1e-6 + integration_error) << model.spec();
  }

  std::vector<double> observed(expected.size() + 1, 0.0);  // last: failed draws
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int s = 0; s < samples; ++s) {
    const auto draw = model.sample_incident(j, {uniform(rng), uniform(rng), uniform(rng)});
    if (!draw) {
      observed.back() += 1.0;
      continue;
    }
    const double t = std::acos(std::clamp(draw->i.z, -1.0, 1.0));
    double q = std::atan2(draw->i.y, draw->i.x);
    if (q < 0.0) q += 2.0 * pi;
    const int a = std::min(kThetaBins - 1, static_cast<int>(t / (0.5 * pi) * kThetaBins));
    const int b = std::min(kPhiBins - 1, static_cast<int>(q / (2.0 * pi) * kPhiBins));
    observed[a * kPhiBins + b] += 1.0;
  }
  out.observed_success = 1.0 - observed.back() / samples;
  std::vector<double> expected_counts(expected.size() + 1);
  for (std::size_t k = 0; k < expected.size(); ++k) expected_counts[k] = expected[k] * samples;
  expected_counts.back() = std::max(0.0, 1.0 - out.expected_total) * samples;

  // Pool the bins with fewer than 5 expected draws (pbrt-v4's rule), then sum (O - E)^2 / E.
  double chsq = 0.0, pooled_observed = 0.0, pooled_expected = 0.0;
  int cells = 0;
  for (std::size_t k = 0; k < expected_counts.size(); ++k) {
    if (expected_counts[k] < 5.0) {
      pooled_observed += observed[k];
      pooled_expected += expected_counts[k];
      continue;
    }
    const double d = observed[k] - expected_counts[k];
    chsq += d * d / expected_counts[k];
    ++cells;
  }
  if (pooled_expected > 0.0 || pooled_observed > 0.0) {
    const double d = pooled_observed - pooled_expected;
    chsq += d * d / std::max(pooled_expected, 5.0);
    ++cells;
  }
  out.dof = cells - 1;
  out.p_value = out.dof > 0 ? boost::math::cdf(boost::math::complement(boost::math::chi_squared(out.dof), chsq)) : 1.0;
  return out;
}

struct Case {
  std::string spec;
  double success;  ///< probability that a draw succeeds (1 unless lumps leave the disk; < 0 unknown)
};

void expect_fits(const Case& c, const std::vector<double>& thetas, int samples = 400000) {
  const ModelPtr model = parse_model(c.spec);
  unsigned seed = 7;
  for (double theta : thetas)
    for (double phi : {0.0, 37.0}) {
      const Vec3 j = outgoing(theta, phi);
      const ChiSquare r = chi_square(*model, j, samples, seed++, c.success);
      EXPECT_GT(r.p_value, kSignificance) << c.spec << " at theta_o = " << theta << ", phi_o = " << phi
                                          << ": chi-square p = " << r.p_value << " (dof " << r.dof << ")";
    }
}

TEST(SamplingChiSquare, HvdEmpiricalScalingProjection) {
  expect_fits({"hvd-empirical:cd=0.5,f0=0.3,k=0,ns=20,nr=10", 1.0}, {0.0, 30.0, 60.0, 80.0});
  expect_fits({"hvd-empirical:cd=0.2,f0=0.6,k=0.4,ns=50,nr=5,rr=0.6", 1.0}, {10.0, 45.0, 75.0});
  expect_fits({"hvd-empirical:cd=0.3,f0=0.5,k=0.3,ns=30,nr=10,rsu=1,rsv=0.3,rru=0.4,rrv=1", 1.0}, {20.0, 70.0});
}

TEST(SamplingChiSquare, HvdEmpiricalNearGrazing) {
  // R_s = 1 - sin(85 deg) = 0.0038: a lobe of a few tenths of a degree.
  expect_fits({"hvd-empirical:cd=0.5,f0=0.04,k=0,ns=10,nr=10", 1.0}, {85.0});
}

TEST(SamplingChiSquare, HvdFitOrthogonalProjectionInsideAndOffTheDisk) {
  // Inside the disk for every theta_o <= 60 deg (R <= 1 - sin 60 = 0.134): every draw succeeds.
  expect_fits({"hvd-fit:cd=0.5,f0=0.2,f90=0.9,k=0.4,n1=20,r1=0.12,n2=5,r2=0.06", 1.0}, {0.0, 40.0, 60.0});
  // Off the disk: draws fail with the probability of the lost energy; the failures are a bin.
  const ModelPtr off = parse_model("hvd-fit:cd=0.1,f0=0.5,f90=0.9,k=0.4,n1=2,r1=0.9,n2=1,r2=1.5");
  for (double theta : {30.0, 70.0}) {
    const Vec3 j = outgoing(theta, 0.0);
    // Success probability = ∫ pdf over the hemisphere (cubature), checked against the draws.
    const Estimate success = [&] {
      std::array<std::vector<double>, 2> cuts{std::vector<double>{0.0, 0.25 * pi, 0.5 * pi},
                                              std::vector<double>{0.0, pi, 2.0 * pi}};
      const auto f = pointwise<2>([&](double t, double q) {
        return off->pdf_incident(j, {std::sin(t) * std::cos(q), std::sin(t) * std::sin(q), std::cos(t)}) * std::sin(t);
      });
      CubatureOptions o;
      o.abs_tol = 1e-10;
      return adaptive_cubature<2>(f, cuts, o);
    }();
    EXPECT_LT(success.value, 0.99);  // the lumps really hang off the disk here
    const ChiSquare r = chi_square(*off, j, 400000, 99, success.value);
    EXPECT_GT(r.p_value, kSignificance) << "off-disk hvd-fit at " << theta << " deg: p = " << r.p_value;
  }
}

TEST(SamplingChiSquare, WardIsotropicAndAnisotropic) {
  expect_fits({"ward:rho_d=0.3,rho_s=0.5,alpha=0.15", -1.0}, {0.0, 40.0, 70.0});
  expect_fits({"ward-aniso:rho_d=0.1,rho_s=0.6,alpha_x=0.08,alpha_y=0.3", -1.0}, {20.0, 60.0});
}

TEST(SamplingChiSquare, GgxVisibleNormals) {
  // Draws reflected below the horizon fail; their share is not known in closed form (-1): the
  // failure bin then carries 1 - the integral of the pdf, which the draws must match too.
  expect_fits({"ggx:alpha=0.3,f0=0.04", -1.0}, {0.0, 40.0, 70.0, 85.0});
  expect_fits({"ggx:alpha=0.05,g2=separable", -1.0}, {30.0, 80.0});
  expect_fits({"ggx:alpha_x=0.1,alpha_y=0.5", -1.0}, {20.0, 60.0});
  // ggx-ms: the visible-normal draw with probability E(mu_j), else a cosine draw (models/ggx_ms.h).
  expect_fits({"ggx-ms:alpha=0.5", -1.0}, {0.0, 60.0, 85.0});
}

TEST(SamplingChiSquare, AshikhminShirleyHalfwayDraws) {
  // The paper's halfway-vector draw (models/ashikhmin_shirley.h) mixed with cosine draws; draws
  // reflected below the horizon fail (-1: their share comes from the pdf's integral).
  expect_fits({"ashikhmin-shirley:rd=0.5,rs=0.05,nu=100,nv=100", -1.0}, {0.0, 45.0, 80.0});
  expect_fits({"ashikhmin-shirley:rd=0.2,rs=0.3,nu=10,nv=1000", -1.0}, {20.0, 70.0});
  expect_fits({"ashikhmin-shirley:rd=0,rs=1,nu=0,nv=0", -1.0}, {60.0});
}

TEST(SamplingChiSquare, SchlickHalfwayDraws) {
  // Schlick's zenith draw (exact for Z) and his azimuth map with its own exact density.
  expect_fits({"schlick:c=0.5,r=0.1,p=1", -1.0}, {0.0, 50.0, 80.0});
  expect_fits({"schlick:c=0.2,r=0.3,p=0.1", -1.0}, {30.0, 70.0});
}

TEST(SamplingChiSquare, DefaultCosineSamplingAndMixtures) {
  expect_fits({"charlie:alpha=0.3", 1.0}, {30.0, 80.0});
  expect_fits({"specular:alpha=8", 1.0}, {0.0, 60.0});
  expect_fits({"0.5*lambert + 0.5*hvd-empirical:cd=0.5,f0=0.3,k=0.5,ns=20,nr=10", 1.0}, {30.0});
}

TEST(SamplingChiSquare, DetectsAWrongPdf) {
  // A sampler that draws from one lump width but reports another must be rejected: the test can fail.
  class Skewed final : public Model {
   public:
    std::string spec() const override { return "skewed"; }
    Traits traits() const override { return {}; }
    double f(const Vec3&, const Vec3&) const noexcept override { return 0.0; }
    std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override {
      auto s = Model::sample_incident(j, {u[0], u[1] * u[1], u[2]});  // not cosine-distributed any more
      if (s) s->pdf = pdf_incident(j, s->i);
      return s;
    }
  } skewed;
  const ChiSquare r = chi_square(skewed, outgoing(30.0, 0.0), 200000, 3, 1.0);
  EXPECT_LT(r.p_value, 1e-12);
}

TEST(SamplingWeights, HvdWeightIsConstantUpToGrazing) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const std::string spec : {"hvd-empirical:cd=0.7,f0=0.04,k=0.3,ns=100,nr=10",
                                 "hvd-empirical:cd=1,eta=1.5,k=0,ns=1000,nr=10,rsu=1,rsv=0.05",
                                 "hvd-fit:cd=0.4,f0=0.1,f90=1,k=0.5,n1=50,r1=0.3,n2=5,r2=0.9"}) {
    const ModelPtr model = parse_model(spec);
    const ModelSpec given = parse_spec(spec).terms.front().model;
    const bool fit = given.name == "hvd-fit";
    const auto& v = given.values;
    for (double theta : {0.0, 45.0, 80.0, 89.0, 89.9, 89.99}) {
      const Vec3 j = outgoing(theta, 25.0);
      const double F = fit ? hvd::schlick(j.z, v.at("f0"), v.at("f90"))
                           : hvd::schlick(j.z, v.count("eta") ? hvd::f0_from_eta(v.at("eta")) : v.at("f0"));
      const double cd = v.at("cd");
      const double expected = (1.0 - F) * cd + F;
      int drawn = 0;
      for (int s = 0; s < 20000; ++s) {
        const auto draw = model->sample_incident(j, {uniform(rng), uniform(rng), uniform(rng)});
        if (!draw) continue;
        ++drawn;
        ASSERT_NEAR(model->pdf_incident(j, draw->i), draw->pdf, 1e-12 * draw->pdf);
        const double weight = model->f(draw->i, j) * draw->i.z / draw->pdf;
        ASSERT_NEAR(weight, expected, 1e-9 * expected)
            << spec << " theta_o " << theta << " i = (" << draw->i.x << ", " << draw->i.y << ", " << draw->i.z << ")";
      }
      if (!fit) { EXPECT_EQ(drawn, 20000) << spec << " at " << theta << " deg: the lumps lie on the disk"; }
    }
  }
}

TEST(SamplingWeights, MeanWeightEstimatesTheLawOfDarkening) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const std::string spec :
       {"specular:alpha=8", "minnaert:xi=0.5", "asperity:alpha=2", "ward:rho_d=0.3,rho_s=0.5,alpha=0.15",
        "ggx:alpha=0.3,f0=0.04", "ggx:alpha_x=0.1,alpha_y=0.5,g2=separable", "charlie:alpha=0.3", "ggx-ms:alpha=0.5",
        "ashikhmin-shirley:rd=0.3,rs=0.2,nu=10,nv=300", "schlick:c=0.3,r=0.2,p=0.3",
        "0.6*minnaert:xi=1 + 0.4*hvd-empirical:cd=0.5,f0=0.2,k=0.5,ns=20,nr=10"}) {
    const ModelPtr model = parse_model(spec);
    const Vec3 j = outgoing(50.0, 10.0);
    const int n = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int s = 0; s < n; ++s) {
      const auto draw = model->sample_incident(j, {uniform(rng), uniform(rng), uniform(rng)});
      const double w = draw ? model->f(draw->i, j) * draw->i.z / draw->pdf : 0.0;
      sum += w;
      sum2 += w * w;
    }
    const double mean = sum / n, standard_error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    const Estimate h = darkening(*model, j, CubatureOptions{});
    EXPECT_NEAR(mean, h.value, 5.0 * standard_error + h.error) << spec;
  }
}

}  // namespace
}  // namespace ganzfeld
