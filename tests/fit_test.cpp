// fit/: samples and their measures, the metrics against hand-computed values, the parameter
// space, recovery of known parameters from noise-free data (analytic and through a MERL file),
// interruption, non-convergence, and the halfway-vector disk density (reports/disk.h).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "export/brdf_export.h"
#include "fit/fit.h"
#include "fit/law_difference.h"
#include "fit/parameters.h"
#include "fit/samples.h"
#include "models/measured.h"
#include "models/spec.h"
#include "reports/disk.h"
#include "tests/temp_dir.h"
#include "util/error.h"

namespace ganzfeld::fit {
namespace {

using std::numbers::pi;
using testing_support::temp_dir;

/// Recovery from noise-free data: the search ends once E_rel < 1e-8 (fit/fit.h, kExactFit), which
/// pins well-determined parameters to ~1e-8; along hvd-fit's n/R² valley the exponent may still be
/// ~1e-5 off (measured 6e-6). The target is 1e-3.
constexpr double kRecoveryRelative = 1e-4;
/// The cell measures of the full 90 x 90 x 180 grid sum to (2π)² up to the grid's discretization
/// of the horizon (cells straddling it count whole or not at all).
constexpr double kMeasureRelative = 0.02;

SampleOptions coarse_grid() {
  SampleOptions o;
  o.grid = {45, 15, 15};
  return o;
}

double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

TEST(FitSamples, MeasuresSumToTheSquareOfTheHemisphere) {
  // Every valid pair of the full grid, no angle left out: ∫∫ dω_i dω_o over two hemispheres.
  SampleOptions o;
  o.grid = {90, 90, 180};
  o.max_theta_deg = 90.0;
  const FitData d = sample_data(*parse_model("lambert"), o);
  double sum = 0.0;
  for (double w : d.weight) sum += w;
  EXPECT_NEAR(sum / (4.0 * pi * pi), 1.0, kMeasureRelative) << d.size() << " samples";
}

TEST(FitSamples, MerlNodesAreTheModelGridAtTheSameCounts) {
  const std::string spec = "cook-torrance:kd=0.3,ks=0.6,m=0.2,eta=1.5,k=0.5";
  const std::string path = temp_dir() + "/ct.binary";
  exporting::write_merl(*parse_model(spec), path);
  const FitData from_file = sample_data(*parse_model("merl:file=" + path), coarse_grid());
  const FitData from_model = sample_data(*parse_model(spec), coarse_grid());
  ASSERT_EQ(from_file.size(), from_model.size());
  for (std::size_t k = 0; k < from_file.size(); k += 97) {
    EXPECT_NEAR(glm::length(from_file.i[k] - from_model.i[k]), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(from_file.j[k] - from_model.j[k]), 0.0, 1e-12);
    // Stored as f / scale in float64 and read back times the scale: rounding only.
    EXPECT_NEAR(from_file.value[k], from_model.value[k], 1e-13 * (1.0 + from_model.value[k]));
    EXPECT_DOUBLE_EQ(from_file.weight[k], from_model.weight[k]);
  }
}

TEST(FitSamples, GrazingPairsAreLeftOut) {
  SampleOptions o = coarse_grid();
  o.max_theta_deg = 60.0;
  const FitData d = sample_data(*parse_model("lambert"), o);
  for (std::size_t k = 0; k < d.size(); ++k) {
    ASSERT_GE(d.i[k].z, std::cos(60.0 * pi / 180.0) - 1e-12);
    ASSERT_GE(d.j[k].z, std::cos(60.0 * pi / 180.0) - 1e-12);
  }
}

TEST(FitSamples, RefusesAGridThatDoesNotDivideMerlNodes) {
  const std::string path = temp_dir() + "/lambert.binary";
  exporting::write_merl(*parse_model("lambert"), path);
  SampleOptions o;
  o.grid = {90, 40, 30};
  EXPECT_THROW(sample_data(*parse_model("merl:file=" + path), o), InputError);
  EXPECT_THROW(parse_grid("90x30"), InputError);
  EXPECT_THROW(parse_grid("1x30x30"), InputError);
  EXPECT_EQ(parse_grid("45x15x15"), (std::array<int, 3>{45, 15, 15}));
}

TEST(FitSamples, NoisyExportsScatterByTheirSigmaAndRepeatWithTheirSeed) {
  const ModelPtr ward = parse_model("ward:rho_d=0.4,rho_s=0.2,alpha=0.15");
  const std::string path = temp_dir() + "/noisy.binary";
  exporting::write_merl(*ward, path, {0.02, 5});
  const FitData noisy = sample_data(*parse_model("merl:file=" + path), coarse_grid());
  const FitData exact = sample_data(*ward, coarse_grid());
  ASSERT_EQ(noisy.size(), exact.size());
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t k = 0; k < noisy.size(); ++k) {
    const double z = (noisy.value[k] / exact.value[k] - 1.0) / 0.02;
    sum += z;
    sum2 += z * z;
  }
  const double n = static_cast<double>(noisy.size()), mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // Standard normal draws: the mean within 5 standard errors of 0, the deviation within 5% of 1.
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sd, 1.0, 0.05);
  EXPECT_EQ(exporting::merl_bytes(*ward, {0.02, 5}), exporting::merl_bytes(*ward, {0.02, 5}));
  EXPECT_NE(exporting::merl_bytes(*ward, {0.02, 5}), exporting::merl_bytes(*ward, {0.02, 6}));
}

TEST(FitMetrics, MatchHandComputedValues) {
  // Two samples: weights 1 and 3, cos θ_i 1 and 0.5, data 2 and 4, model 2 and 2.
  FitData d;
  d.i = {{0, 0, 1}, {std::sqrt(0.75), 0, 0.5}};
  d.j = d.i;
  d.value = {2.0, 4.0};
  d.weight = {1.0, 3.0};
  const MetricValues m = measure(d, {2.0, 2.0});
  // E = sqrt((0 + 3·((4 − 2)·0.5)²) / 4); E_rel over Σ w d² c² = 1·4·1 + 3·16·0.25 = 16.
  EXPECT_DOUBLE_EQ(m.ngan_rms, std::sqrt(3.0 / 4.0));
  EXPECT_DOUBLE_EQ(m.ngan_relative, std::sqrt(3.0 / 16.0));
  // E_log = sqrt(3·(ln(1 + 4·0.5) − ln(1 + 2·0.5))² / 4).
  EXPECT_NEAR(m.log_rms, std::sqrt(3.0 * std::pow(std::log(3.0) - std::log(2.0), 2) / 4.0), 1e-15);
  EXPECT_DOUBLE_EQ(objective(Metric::ngan, m), 3.0 / 16.0);
  EXPECT_NEAR(objective(Metric::log, m), 3.0 * std::pow(std::log(1.5), 2) / 4.0, 1e-15);
  EXPECT_THROW(parse_metric("l2"), InputError);
}

TEST(FitParameters, FreeParametersComeFromTheCanonicalSpec) {
  const ParameterSpace ggx("ggx:roughness=0.3", {});
  ASSERT_EQ(ggx.free().size(), 2u);  // alpha (from roughness) and f0; g2 is a choice
  EXPECT_EQ(ggx.free()[0].name, "alpha");
  EXPECT_NEAR(ggx.free()[0].start, 0.09, 1e-15);
  EXPECT_EQ(ggx.free()[1].name, "f0");
  const ParameterSpace hvd("hvd-empirical", {"k=0.5"});
  for (const FreeParameter& p : hvd.free()) EXPECT_NE(p.name, "k");
  EXPECT_NE(hvd.spec_at(hvd.start()).find("k=0.5"), std::string::npos);
  const ParameterSpace mix("lambert + ggx", {"ggx.f0=0.04"});
  std::vector<std::string> names;
  for (const FreeParameter& p : mix.free()) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"ggx.alpha", "ggx.weight"}));
}

TEST(FitParameters, MappingsRoundTripInsideTheBounds) {
  for (const char* spec : {"hvd-fit", "ggx", "lafortune", "minnaert"}) {
    const ParameterSpace space(spec, {});
    for (const FreeParameter& p : space.free())
      for (double u : {0.0, 0.1, 0.5, 0.9, 1.0}) {
        const double x = p.from_unit(u);
        ASSERT_GE(x, p.lo) << spec << " " << p.name;
        ASSERT_LE(x, p.hi) << spec << " " << p.name;
        EXPECT_NEAR(p.to_unit(x), u, 1e-12) << spec << " " << p.name;
      }
  }
}

TEST(FitParameters, RefusesBadInput) {
  EXPECT_THROW(ParameterSpace("lambert", {}), InputError);                                    // no parameter at all
  EXPECT_THROW(ParameterSpace("perfect-backscatter", {}), InputError);                        // an integer only
  EXPECT_THROW(ParameterSpace("ward", {"beta=1"}), InputError);                               // unknown
  EXPECT_THROW(ParameterSpace("ward", {"alpha=3"}), InputError);                              // out of range
  EXPECT_THROW(ParameterSpace("ward", {"alpha"}), InputError);                                // not KEY=VALUE
  EXPECT_THROW(ParameterSpace("ward", {"rho_d=0.5", "rho_s=0.1", "alpha=0.2"}), InputError);  // nothing left
  EXPECT_THROW(ParameterSpace("ggx", {"roughness=0.5"}), InputError);                         // contradicts alpha
}

/// Fits `truth`'s model from its registry defaults to `data` and returns the largest relative
/// parameter error.
double recovery_error(const std::string& truth, const FitData& data, FitResult* out = nullptr) {
  const std::string name = canonical_spec(truth).terms.front().model.name;
  const FitResult r = fit_model(data, name, {});
  EXPECT_TRUE(r.converged) << truth << ": " << r.stop_reason;
  const auto truth_values = ParameterSpace(name, {}).values_of(truth);
  double worst = 0.0;
  for (const auto& [pname, value] : r.parameters)
    for (const auto& [tname, t] : truth_values)
      if (tname == pname) worst = std::max(worst, relative(value, t));
  if (out) *out = r;
  return worst;
}

TEST(FitRecovery, KnownParametersFromAnalyticData) {
  for (const char* truth : {"ward:rho_d=0.4,rho_s=0.2,alpha=0.15", "ggx:alpha=0.2,f0=0.6",
                            "oren-nayar:sigma=0.4,rho=0.7", "blinn-phong:kd=0.4,ks=0.3,n=50"})
    EXPECT_LE(recovery_error(truth, sample_data(*parse_model(truth), coarse_grid())), kRecoveryRelative) << truth;
}

TEST(FitRecovery, TwoLumpsThroughAMerlFile) {
  const std::string truth = "hvd-fit:cd=0.4,f0=0.05,f90=0.8,k=0.3,n1=200,r1=0.3,n2=20,r2=0.6";
  const std::string path = temp_dir() + "/hvd.binary";
  exporting::write_merl(*parse_model(truth), path);
  FitResult r;
  EXPECT_LE(recovery_error(truth, sample_data(*parse_model("merl:file=" + path), coarse_grid()), &r),
            kRecoveryRelative);
  EXPECT_LT(r.metrics.ngan_relative, 1e-6);
}

TEST(FitRecovery, AMixtureWeight) {
  const std::string truth = "0.6*lambert + 0.4*ggx:alpha=0.3,f0=0.8";
  const FitResult r = fit_model(sample_data(*parse_model(truth), coarse_grid()), "lambert + ggx", {});
  ASSERT_EQ(r.parameters.size(), 3u);
  EXPECT_NEAR(r.parameters[0].second, 0.3, 0.3 * kRecoveryRelative);  // ggx.alpha
  EXPECT_NEAR(r.parameters[1].second, 0.8, 0.8 * kRecoveryRelative);  // ggx.f0
  EXPECT_NEAR(r.parameters[2].second, 0.4 / 0.6, kRecoveryRelative);  // ggx.weight, relative to lambert's
}

TEST(FitRecovery, TheLogMetricFindsTheSameParameters) {
  const std::string truth = "ward:rho_d=0.4,rho_s=0.2,alpha=0.15";
  FitOptions o;
  o.metric = Metric::log;
  const FitResult r = fit_model(sample_data(*parse_model(truth), coarse_grid()), "ward", o);
  EXPECT_NEAR(r.parameters[2].second, 0.15, 0.15 * kRecoveryRelative);
}

TEST(FitSearch, ABudgetTooSmallIsReportedNotConverged) {
  FitOptions o;
  o.max_evaluations = 5;
  o.starts = 1;
  const FitResult r = fit_model(sample_data(*parse_model("ward:alpha=0.3"), coarse_grid()), "ward", o);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.stop_reason, "evaluation budget reached");
  EXPECT_FALSE(r.spec.empty());  // the best point so far, as a spec
  EXPECT_LE(r.metrics.ngan_relative, r.start_metrics.ngan_relative);
}

TEST(FitSearch, AnInterruptionKeepsTheBestPointSoFar) {
  FitOptions o;
  int calls = 0;
  o.interrupted = [&] { return ++calls >= 40; };
  const FitResult r = fit_model(sample_data(*parse_model("ward:alpha=0.3"), coarse_grid()), "ward", o);
  EXPECT_TRUE(r.interrupted);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.stop_reason, "interrupted");
  EXPECT_LE(r.evaluations, 41);
  EXPECT_EQ(r.starts_run, 1);
  EXPECT_LE(r.metrics.ngan_relative, r.start_metrics.ngan_relative);
}

TEST(FitLaws, AnExactFitHasTheDataLaws) {
  const ModelPtr m = parse_model("ward:rho_d=0.4,rho_s=0.2,alpha=0.15");
  const LawDifference d = law_difference(*m, *m, 1e-6);
  EXPECT_EQ(d.points.size(), law_geometries().size());
  EXPECT_EQ(d.max_g + d.max_h + d.max_a, 0.0);
  const LawDifference other = law_difference(*m, *parse_model("lambert"), 1e-6);
  EXPECT_GT(other.max_h, 0.1);  // Lambert's h is 1, Ward's about 0.6
}

TEST(DiskView, LambertIsUniformOnTheOrthogonalDisk) {
  // p = ρ = 1/π everywhere on the disk (eq. 24), 0 off it.
  const ModelPtr lambert = parse_model("lambert");
  const Vec3 j{std::sin(0.5), 0.0, std::cos(0.5)};
  for (const hvd::Uv h : {hvd::Uv{0.0, 0.0}, hvd::Uv{j.x + 0.5, 0.3}, hvd::Uv{j.x - 0.9, 0.0}})
    EXPECT_NEAR(disk_density(*lambert, DiskProjection::orthogonal, j, h), 1.0 / pi, 1e-14);
  EXPECT_EQ(disk_density(*lambert, DiskProjection::orthogonal, j, {j.x + 1.01, 0.0}), 0.0);
}

TEST(DiskView, DensitiesIntegrateToTheLawOfDarkening) {
  // ∫_disk p dA = ∫ ρ (ω_i·N) dω_i = h(ω_o) in both projections (eq. 8–11, 19, 23).
  const ModelPtr ct = parse_model("cook-torrance:kd=0.3,ks=0.6,m=0.3,eta=1.5,k=0.5");
  const Vec3 j{std::sin(0.6), 0.0, std::cos(0.6)};
  CubatureOptions o;
  o.abs_tol = 1e-7;
  const double h = darkening(*ct, j, o).value;
  constexpr int kGrid = 1200;
  for (DiskProjection projection : {DiskProjection::orthogonal, DiskProjection::scaling}) {
    double sum = 0.0;
    const double step = 2.0 / kGrid;
    for (int a = 0; a < kGrid; ++a)
      for (int b = 0; b < kGrid; ++b)
        sum += disk_density(*ct, projection, j, {j.x - 1.0 + (a + 0.5) * step, -1.0 + (b + 0.5) * step}) * step * step;
    // Midpoint rule on a 1200² grid over a density with a rim: 0.5% (measured 0.1%).
    EXPECT_NEAR(sum, h, 5e-3 * h) << (projection == DiskProjection::orthogonal ? "orthogonal" : "scaling");
  }
}

TEST(DiskView, TheSpecularLumpTightensTowardGrazing) {
  // A microfacet lobe of fixed slope width maps to |h_uv| = 2 cos θ_d sin θ_h on the orthogonal
  // disk: its spread falls with θ_o, as Edwards et al. describe for measured plastic (Fig. 13).
  const ModelPtr plastic = parse_model("cook-torrance:kd=0.3,ks=0.7,m=0.05,eta=1.5,k=0");
  EXPECT_GT(disk_spread(*plastic, 0.0), disk_spread(*plastic, 45.0));
  EXPECT_GT(disk_spread(*plastic, 45.0), 1.5 * disk_spread(*plastic, 75.0));
  // hvd-fit's lumps do not depend on ω_o: the same spread while they lie inside the disk (at 45°
  // its rim passes 0.29 from the origin; the lumps reach 0.25), to the grid's resolution.
  const ModelPtr lumps = parse_model("hvd-fit:cd=0.3,f0=0.05,k=0.3,n1=100,r1=0.2,n2=10,r2=0.25");
  EXPECT_NEAR(disk_spread(*lumps, 45.0) / disk_spread(*lumps, 0.0), 1.0, 0.02);
}

}  // namespace
}  // namespace ganzfeld::fit
