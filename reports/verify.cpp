#include "reports/verify.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "models/kp_lobes.h"
#include "models/mixture.h"
#include "models/registry.h"
#include "models/spec.h"
#include "reports/verify_support.h"

namespace ganzfeld {

namespace {

using std::numbers::pi;
using namespace verify_support;

const char* kSrc = "Koenderink & Pont, Material Properties and Extended Sources for Surface Rendering";

// The grid. Extremes on purpose: sky pole at the nadir (-1) and 0.999 from it, on the horizon
// (0) and just above (1e-6), at the zenith; views grazing (0, 1e-6) and normal.
const std::vector<double> kCosPole{-1.0, -0.999, -0.7, -0.3, 0.0, 1e-6, 0.3, 0.7, 0.999, 1.0};
const std::vector<double> kCosView{0.0, 1e-6, 0.25, 0.5, 0.75, 1.0};
const std::vector<double> kPhiDeg{0.0, 45.0, 90.0, 135.0, 180.0};
const std::vector<double> kCos{0.0, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999, 1.0};

Sample from_estimate(double printed, double corrected, const Estimate& e) {
  return {printed, corrected, e.value, e.error, e.converged, 1};
}

/// check_meta of a claim printed in K&P at `where`.
CheckResult meta(std::string id, const std::string& where, std::string models, std::string printed,
                 std::string corrected = "", std::string explanation = "") {
  return check_meta(std::move(id), std::string(kSrc) + ", " + where, std::move(models), std::move(printed),
                    std::move(corrected), std::move(explanation));
}

using PairForm = std::function<double(const Vec3& i, const Vec3& j)>;
using CosForm = std::function<double(double mu)>;

/// g over (sky pole i·n) × (view j·n) × (azimuth of j from i).
std::vector<Job> vignetting_jobs(ModelPtr model, PairForm printed, PairForm corrected = nullptr) {
  std::vector<Job> jobs;
  for (double c : kCosPole)
    for (double mu : kCosView)
      for (double phi : kPhiDeg)
        jobs.push_back([=] {
          const Vec3 i = direction_from_cos(c), j = direction_from_cos(mu, phi * pi / 180);
          return from_estimate(printed(i, j), corrected ? corrected(i, j) : kNaN,
                               vignetting(*model, i, j, reference_options()));
        });
  return jobs;
}

/// h(j·n) or a(i·n) over kCos.
std::vector<Job> cos_jobs(ModelPtr model, Law law, CosForm printed) {
  std::vector<Job> jobs;
  for (double mu : kCos)
    jobs.push_back([=] {
      const Vec3 d = direction_from_cos(mu);
      return from_estimate(printed(mu), kNaN, evaluate_law(*model, law, d, d, reference_options()));
    });
  return jobs;
}

/// max over i·n of a(i), with the argmax refined by golden section when it is interior.
struct Maximum {
  double value = 0.0, error = 0.0;
  bool converged = true;
  long points = 0;
};
Maximum max_albedo(const Model& model) {
  Maximum m;
  auto a = [&](double mu) {
    const Estimate e = albedo(model, direction_from_cos(mu), reference_options());
    m.error = std::max(m.error, e.error);
    m.converged = m.converged && e.converged;
    ++m.points;
    return e.value;
  };
  constexpr int kSteps = 40;
  std::vector<double> mus{1e-6};
  for (int k = 0; k <= kSteps; ++k) mus.push_back(double(k) / kSteps);
  std::sort(mus.begin(), mus.end());
  std::vector<double> values;
  for (double mu : mus) values.push_back(a(mu));
  const auto best = std::max_element(values.begin(), values.end()) - values.begin();
  m.value = values[best];
  if (best > 0 && best + 1 < static_cast<long>(mus.size())) {
    double lo = mus[best - 1], hi = mus[best + 1];
    const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 60; ++it) {
      const double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
      if (a(x1) > a(x2)) hi = x2;
      else lo = x1;
    }
    m.value = std::max(m.value, a(0.5 * (lo + hi)));
  }
  return m;
}

/// "The constant is the largest compatible with energy conservation": max_i a(i) = 1 with the
/// printed constant; corrected: with ours.
std::vector<Job> norm_jobs(const std::string& name, const std::vector<double>& params,
                           std::function<double(double)> printed_constant, std::function<double(double)> our_constant) {
  std::vector<Job> jobs;
  for (double p : params)
    jobs.push_back([=] {
      const std::string key = name == "minnaert" ? "xi" : "alpha";
      const ModelPtr model = parse_model(name + ":" + key + "=" + format_number(p));
      const Maximum m = max_albedo(*model);
      const double printed = m.value * printed_constant(p) / our_constant(p);
      return Sample{printed, m.value, 1.0, m.error, m.converged, m.points};
    });
  return jobs;
}

std::string list(const std::vector<double>& v, const std::string& key) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : ", ") + key + "=" + format_number(x);
  return s;
}

// ---------------------------------------------------------------------------------------------
std::vector<CheckResult> lambert_checks() {
  const ModelPtr m = parse_model("lambert");
  return {
      run_check(meta("lambert.g", "Extended Sources, hemispherical diffuse beam", "lambert", "g_L = (1 + i·n)/2"),
                vignetting_jobs(m, [](const Vec3& i, const Vec3&) { return lambert::g(i.z); })),
      run_check(meta("lambert.h", "Extended Sources, Ganzfeld", "lambert", "h_L = 1"),
                cos_jobs(m, Law::h, [](double) { return 1.0; })),
      run_check(meta("lambert.a", "Extended Sources", "lambert", "a_L = 1"),
                cos_jobs(m, Law::a, [](double) { return 1.0; })),
      run_check(meta("lambert.r", "Extended Sources", "lambert", "r_L = 1"),
                {[m] { return from_estimate(1.0, kNaN, double_diffuse(*m, reference_options())); }}),
  };
}

std::vector<CheckResult> minnaert_checks() {
  const std::vector<double> xis{0.3, 1.0, 2.0, 2.7};
  const std::vector<double> xis_wide{1e-6, 0.3, 1.0, 2.7, 50.0};
  auto for_each_xi = [](const std::vector<double>& values, auto make_jobs) {
    std::vector<Job> all;
    for (double xi : values) {
      auto jobs = make_jobs(xi, parse_model("minnaert:xi=" + format_number(xi)));
      all.insert(all.end(), jobs.begin(), jobs.end());
    }
    return all;
  };
  const char* corrected_g =
      "g_d = (j·n)^xi [1/2 + Gamma((3+xi)/2)/(sqrt(pi) Gamma(1+xi/2)) (i·n) 2F1(1/2, -xi/2; 3/2; (i·n)^2)]";
  const char* why_g =
      "At i·n = 0 the sky covers exactly half of the hemisphere, so g must equal h/2 = (j·n)^xi/2, yet the "
      "printed form vanishes there; at i·n = 1 it gives (j·n)^xi/2 instead of h = (j·n)^xi. The printed term "
      "is only the odd part of g in i·n. Differentiating the lune integral with respect to the pole angle gives "
      "dg/d(i·n) = K (1-(i·n)^2)^(xi/2) (j·n)^xi with K = Gamma((3+xi)/2)/(sqrt(pi) Gamma(1+xi/2)); integrating "
      "from i·n = 0, where g = h/2, and using z 2F1(1/2,-b;3/2;z^2) = ∫_0^z (1-t^2)^b dt yields the corrected "
      "form. For xi = 1 it reduces to the printed xi = 1 form (minnaert.g.xi1), which is right. (The paper calls "
      "2F1 a confluent hypergeometric function; it is Gauss's.)";
  return {
      run_check(meta("minnaert.g.xi1", "Bulk Scattering, g_d for xi = 1", "minnaert:xi=1",
                     "g_d = (j·n)/pi (pi - arccos(i·n) + (i·n) sqrt(1 - (i·n)^2))"),
                vignetting_jobs(parse_model("minnaert:xi=1"),
                                [](const Vec3& i, const Vec3& j) { return minnaert::g_xi1_printed(i.z, j.z); })),
      run_check(
          meta("minnaert.g.hyp2f1", "Bulk Scattering, g_d with 2F1", list(xis, "minnaert:xi"),
               "g_d = Gamma((3+xi)/2)/(sqrt(pi) Gamma(1+xi/2)) (i·n) (j·n)^xi 2F1(1/2, -xi/2; 3/2; (i·n)^2)",
               corrected_g, why_g),
          for_each_xi(xis,
                      [](double xi, ModelPtr m) {
                        return vignetting_jobs(
                            m, [xi](const Vec3& i, const Vec3& j) { return minnaert::g_hyp2f1_printed(i.z, j.z, xi); },
                            [xi](const Vec3& i, const Vec3& j) { return minnaert::g(i.z, j.z, xi); });
                      })),
      run_check(
          meta(
              "minnaert.g.betainc", "Bulk Scattering, g_d with the incomplete beta function", list(xis, "minnaert:xi"),
              "g_d = Gamma((3+xi)/2)/(xi sqrt(pi) Gamma(xi/2)) (j·n)^xi B_{(i·n)^2}(1/2, 1 + xi/2)",
              "g_d = (j·n)^xi [1/2 + sign(i·n) Gamma((3+xi)/2)/(xi sqrt(pi) Gamma(xi/2)) B_{(i·n)^2}(1/2, 1 + xi/2)]",
              "The same missing half-hemisphere term 1/2 as minnaert.g.hyp2f1 (the printed coefficient is right: "
              "B_{z^2}(1/2, 1+xi/2) = 2 z 2F1(1/2, -xi/2; 3/2; z^2) and xi Gamma(xi/2) = 2 Gamma(1+xi/2)); in addition "
              "B_{(i·n)^2} is even in i·n, so for a sky pole below the horizon the odd part needs the factor "
              "sign(i·n). The text's 'for integer alpha' is a slip: the form holds for every real xi >= 0."),
          for_each_xi(xis,
                      [](double xi, ModelPtr m) {
                        return vignetting_jobs(
                            m, [xi](const Vec3& i, const Vec3& j) { return minnaert::g_betainc_printed(i.z, j.z, xi); },
                            [xi](const Vec3& i, const Vec3& j) { return minnaert::g(i.z, j.z, xi); });
                      })),
      run_check(meta("minnaert.h", "Bulk Scattering", list(xis_wide, "minnaert:xi"), "h_d = (j·n)^xi"),
                for_each_xi(xis_wide,
                            [](double xi, ModelPtr m) {
                              return cos_jobs(m, Law::h, [xi](double mu) { return minnaert::h(mu, xi); });
                            })),
      run_check(meta("minnaert.a", "Bulk Scattering", list(xis_wide, "minnaert:xi"), "a_d = (i·n)^xi"),
                for_each_xi(xis_wide,
                            [](double xi, ModelPtr m) {
                              return cos_jobs(m, Law::a, [xi](double mu) { return minnaert::a(mu, xi); });
                            })),
      run_check(meta("minnaert.r", "Bulk Scattering", list(xis_wide, "minnaert:xi"), "r_d = 2/(2 + xi)"),
                for_each_xi(xis_wide,
                            [](double xi, ModelPtr m) {
                              return std::vector<Job>{[xi, m] {
                                return from_estimate(minnaert::r(xi), kNaN, double_diffuse(*m, reference_options()));
                              }};
                            })),
      run_check(meta("minnaert.norm", "Bulk Scattering", list({0.5, 1.0, 2.0}, "minnaert:xi"),
                     "C_d = (2 + xi)/(2 pi) is the largest constant compatible with energy conservation (max_i a = 1)"),
                norm_jobs("minnaert", {0.5, 1.0, 2.0}, minnaert::C_d, minnaert::C_d)),
  };
}

std::vector<CheckResult> specular_checks() {
  const std::vector<double> alphas{1, 2, 3, 4, 8};
  return {
      run_check(meta("specular.a.alpha1", "Specular reflection", "specular:alpha=1", "a_s = (3 + 2 i·n)/5"),
                cos_jobs(parse_model("specular:alpha=1"), Law::a, specular::a_alpha1_printed)),
      run_check(meta("specular.a.alpha8", "Specular reflection", "specular:alpha=8",
                     "a_s = (24201945 + 33554432 cos t + 9773400 cos 2t - 415212 cos 4t + 10728 cos 6t - 45 cos 8t)"
                     " / 67125248, t = arccos(i·n)"),
                cos_jobs(parse_model("specular:alpha=8"), Law::a, specular::a_alpha8_printed)),
      run_check(meta("specular.norm", "Specular reflection", list(alphas, "specular:alpha"),
                     "C_s = (1 + alpha)(2 + alpha)/(2 pi (2 alpha + 2^-alpha)) is the largest constant compatible "
                     "with energy conservation (max_i a = 1)"),
                norm_jobs("specular", alphas, specular::C_s_printed, cosine_power_lobe_normalization)),
  };
}

std::vector<CheckResult> backscatter_checks() {
  const std::vector<double> alphas{1, 2, 3, 4, 8};
  return {
      run_check(
          meta(
              "backscatter.g.alpha1", "Backscattering, g_b for alpha = 1", "backscatter:alpha=1",
              "g_b = 3/10 (1 + cos theta) + 1/(5 pi) (cos eta - cos(eta + 2 theta) + 2 (pi - theta) sin eta sin zeta), "
              "i·n = cos theta, j·n = sin eta sin zeta, [i,j,n] = -cos zeta sin theta",
              "g_b = 3/10 (1 + cos theta) + sin zeta/(5 pi) (cos eta - cos(eta + 2 theta) + 2 (pi - theta) sin eta)",
              "With i = (sin theta, 0, cos theta) the printed angles put j = (sin zeta cos eta, -cos zeta, sin zeta "
              "sin eta): "
              "zeta is measured from the lune's edge axis and eta is the longitude about it. By linearity g_b = C/2 "
              "[∫_lune (k·n) dk + j·∫_lune (k·n) k dk] with ∫_lune (k·n) dk = pi (1 + cos theta)/2 and ∫_lune (k·n) k "
              "dk "
              "= (2/3 sin^2 theta, 0, 2/3 (pi - theta) + 1/3 sin 2 theta); with C = 6/(5 pi) (see backscatter.norm) "
              "this "
              "is the corrected form. The printed one drops the factor sin zeta from the first two bracket terms, so "
              "it is right only for j in the plane of i and n."),
          vignetting_jobs(parse_model("backscatter:alpha=1"), backscatter::g_alpha1_printed, backscatter::g_alpha1)),
      run_check(meta("backscatter.h.alpha1", "Backscattering", "backscatter:alpha=1", "h_b = (3 + 2 j·n)/5"),
                cos_jobs(parse_model("backscatter:alpha=1"), Law::h, backscatter::h_alpha1_printed)),
      run_check(
          meta("backscatter.norm", "Backscattering", list(alphas, "backscatter:alpha"),
               "C_b = 6/(5 pi 2^alpha) maximizes the reflectance (max_i a = 1)",
               "C_b = (1 + alpha)(2 + alpha)/(2 pi (2 alpha + 2^-alpha)), the same constant as C_s",
               "The printed constant gives a maximal albedo of 1/2 at alpha = 1 (a_b = (3 + 2 i·n)/10) and less for "
               "larger "
               "alpha, contradicting the paper's own alpha = 1 results h_b = (3 + 2 j·n)/5 and 3/10 (1 + cos theta) in "
               "g_b, "
               "which need C = 6/(5 pi): the factor 2^-alpha is counted twice (it is already inside ((1 + "
               "i·j)/2)^alpha; the "
               "printed constant fits (1 + i·j)^alpha). At normal incidence the backscatter lobe coincides with the "
               "specular "
               "lobe and the albedo peaks there (this check finds the maximum over i·n), so the largest admissible "
               "constant equals C_s. ganzfeld implements the corrected constant."),
          norm_jobs("backscatter", alphas, backscatter::C_b_printed, backscatter::C_b)),
  };
}

std::vector<CheckResult> perfect_backscatter_checks() {
  const std::vector<double> alphas{2, 3, 4, 8};
  std::vector<Job> retro;
  for (double alpha : alphas)
    for (double mu : kCos) {
      if (mu == 0.0) continue;  // on the horizon f(i,i) is the 1/0 of a null set
      retro.push_back([=] {
        const ModelPtr m = parse_model("perfect-backscatter:alpha=" + format_number(alpha));
        const Vec3 i = direction_from_cos(mu), n{0, 0, 1};
        return Sample{mu * m->f(i, i), kNaN, m->f(n, n), 0.0, true, 1};
      });
    }
  return {
      run_check(
          meta("perfect-backscatter.norm", "Backscattering, perfect backscatterer",
               list(alphas, "perfect-backscatter:alpha") + " (alpha = 1 is outside the paper's integer alpha >= 2)",
               "C_pb = (1 + alpha)/(2^(1+alpha) pi) is the largest constant compatible with energy conservation"),
          norm_jobs("perfect-backscatter", alphas, perfect_backscatter::C_pb_printed,
                    perfect_backscatter::C_pb_printed)),
      run_check(meta("perfect-backscatter.retro", "Backscattering, perfect backscatterer",
                     list(alphas, "perfect-backscatter:alpha"),
                     "the radiance (i·n) f(i, i) scattered back towards the source does not depend on i"),
                retro),
  };
}

std::vector<CheckResult> asperity_checks() {
  const std::vector<double> alphas{1, 2, 3, 4, 8};
  return {
      run_check(meta("asperity.g.alpha1", "Asperity Scattering, g_a for alpha = 1", "asperity:alpha=1",
                     "g_a = (1 + i·n)/2 - 4 (j·n)/(3 pi) (pi - arccos(i·n) + (i·n) sqrt(1 - (i·n)^2)) - 1/8 (j·n)^2 "
                     "(i·n - 2)(i·n + 1)^2",
                     "g_a = (1 + i·n)/2 - 2 (j·n)/(3 pi) (pi - arccos(i·n) + (i·n) sqrt(1 - (i·n)^2))",
                     "The printed expression is g_a for alpha = 2, not alpha = 1 (tests/verify_test checks it against "
                     "alpha = 2 "
                     "cubature): (1 - (k·n)(j·n))^2 integrates to ∫_lune (k·n) - 2 (j·n) ∫_lune (k·n)^2 + (j·n)^2 "
                     "∫_lune (k·n)^3 "
                     "with ∫_lune (k·n)^2 dk = 2/3 (pi - arccos c + c sqrt(1 - c^2)) and ∫_lune (k·n)^3 dk = -pi/8 (c "
                     "- 2)(c + 1)^2, "
                     "term for term the printed form. For alpha = 1 only the first two integrals appear, giving the "
                     "corrected form; "
                     "it is consistent with the printed h_a = 1 - 2 (j·n)/3 at i·n = 1."),
                vignetting_jobs(
                    parse_model("asperity:alpha=1"),
                    [](const Vec3& i, const Vec3& j) { return asperity::g_alpha1_printed(i.z, j.z); },
                    [](const Vec3& i, const Vec3& j) { return asperity::g_alpha1(i.z, j.z); })),
      run_check(meta("asperity.h.alpha1", "Asperity Scattering", "asperity:alpha=1", "h_a = 1 - 2 (j·n)/3"),
                cos_jobs(parse_model("asperity:alpha=1"), Law::h, asperity::h_alpha1_printed)),
      run_check(meta("asperity.norm", "Asperity Scattering", list(alphas, "asperity:alpha"),
                     "C_a = 1/pi is as large as is compatible with the plausibility constraints"),
                norm_jobs(
                    "asperity", alphas, [](double) { return asperity::C_a_printed(); },
                    [](double) { return std::numbers::inv_pi; })),
  };
}

const std::vector<std::string> kReciprocalSpecs{"lambert",
                                                "minnaert:xi=0.3",
                                                "minnaert:xi=2",
                                                "specular:alpha=1",
                                                "specular:alpha=8",
                                                "backscatter:alpha=1",
                                                "backscatter:alpha=8",
                                                "perfect-backscatter:alpha=2",
                                                "perfect-backscatter:alpha=5",
                                                "asperity:alpha=1",
                                                "asperity:alpha=4"};

const std::vector<std::string> kMixtureSpecs{
    "0.7*minnaert:xi=1 + 0.3*specular:alpha=8",
    "0.5*lambert + 0.3*backscatter:alpha=4 + 0.2*asperity:alpha=4",
    "0.6*perfect-backscatter:alpha=3 + 0.4*specular:alpha=100",
};

CheckResult reciprocity_check() {
  std::vector<Job> jobs;
  std::string models;
  for (const auto& spec : kReciprocalSpecs) {
    models += (models.empty() ? "" : ", ") + spec;
    for (double mu : kCos)
      jobs.push_back([spec, mu] {
        const ModelPtr m = parse_model(spec);
        const Vec3 d = direction_from_cos(mu);
        const Estimate a = albedo(*m, d, reference_options());
        const Estimate h = darkening(*m, d, reference_options());
        return Sample{a.value, kNaN, h.value, a.error + h.error, a.converged && h.converged, 1};
      });
  }
  return run_check(meta("reciprocity.a_equals_h", "Extended Sources (albedo)", models,
                        "Helmholtz reciprocity implies a(k, n) = h(k, n)"),
                   jobs);
}

/// K&P: a partitive mixture "is non-negative throughout, conforms to Helmholtz reciprocity and does
/// not violate energy conservation if this applies to the individual components". The sample's
/// value is the largest violation found (0 when plausible); we also check that the mixture's
/// albedo is the weighted sum of its lobes' (the linearity our per-lobe tables rely on).
CheckResult mixture_check() {
  std::vector<Job> jobs;
  std::string models;
  for (const auto& spec : kMixtureSpecs) {
    append_model(models, spec);
    jobs.push_back([spec] {
      const ModelPtr m = parse_model(spec);
      std::mt19937_64 rng(20190117);  // fixed seed: a reproducible report
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      std::vector<Vec3> dirs;
      for (double c : {0.0, 1e-6, 1.0}) dirs.push_back(direction_from_cos(c, 2 * pi * unit(rng)));
      for (int k = 0; k < 400; ++k) dirs.push_back(direction_from_cos(unit(rng), 2 * pi * unit(rng)));
      double negativity = 0.0, asymmetry = 0.0;
      long points = 0;
      for (const Vec3& i : dirs)
        for (const Vec3& j : dirs) {
          negativity = std::max(negativity, -m->f(i, j));
          asymmetry = std::max(asymmetry, std::abs(m->f(i, j) - m->f(j, i)));
          ++points;
        }
      const auto lobes = parse_lobes(spec);
      double excess = 0.0, nonlinearity = 0.0, ref_error = 0.0;
      bool converged = true;
      for (double mu : kCos) {
        const Estimate a = albedo(*m, direction_from_cos(mu), reference_options());
        double sum = 0.0, sum_error = 0.0;
        for (const auto& lobe : lobes) {
          const Estimate al = albedo(*lobe.model, direction_from_cos(mu), reference_options());
          sum += lobe.weight * al.value;
          sum_error += lobe.weight * al.error;
          converged = converged && al.converged;
        }
        excess = std::max(excess, a.value - 1.0 - a.error);
        nonlinearity = std::max(nonlinearity, std::abs(a.value - sum));
        ref_error = std::max(ref_error, a.error + sum_error);
        converged = converged && a.converged;
        points += 1;
      }
      const double violation = std::max({negativity, asymmetry, std::max(excess, 0.0), nonlinearity});
      return Sample{violation, kNaN, 0.0, ref_error, converged, points};
    });
  }
  return run_check(meta("mixture.plausible", "Generic, Simple, Analytic BRDFs (partitive mixture)", models,
                        "a partitive mixture of plausible lobes is non-negative, reciprocal and has albedo <= 1; "
                        "reported error: the largest violation (and |a_mix - sum w_k a_k|)"),
                   jobs);
}

}  // namespace

namespace verify_support {

CubatureOptions reference_options() {
  CubatureOptions o;
  o.abs_tol = kReferenceTolerance;
  return o;
}

void append_model(std::string& models, const std::string& spec) { models += (models.empty() ? "" : "; ") + spec; }

CheckResult check_meta(std::string id, std::string source, std::string models, std::string printed,
                       std::string corrected, std::string explanation) {
  CheckResult c;
  c.id = std::move(id);
  c.source = std::move(source);
  c.models = std::move(models);
  c.printed = std::move(printed);
  c.corrected = std::move(corrected);
  c.explanation = std::move(explanation);
  return c;
}

Estimate integrate_over_lune(const Vec3& pole, const std::function<double(const Vec3&)>& F,
                             const std::vector<double>& scales, bool at_horizon, CubatureOptions options) {
  const Lune fr = lune(pole, Vec3{1.0, 0.0, 0.0});
  std::vector<double> t_lines, phi_lines;
  for (double s : scales)
    for (double d = s; d < 1.5; d *= 4.0)
      for (double line : {std::atan(d), -std::atan(d)}) {
        const double x = at_horizon ? (line > 0 ? pi / 2 - d : -pi / 2 + d) : line;
        t_lines.push_back(x);
        phi_lines.push_back(x);
      }
  const auto integrand = pointwise<2>([&](double t, double phi) { return F(fr.direction(t, phi)) * std::cos(t); });
  const double gap = 1e-3 * scales.front();
  return adaptive_cubature<2>(
      integrand, {tidy_cuts(t_lines, -pi / 2, pi / 2, gap), tidy_cuts(phi_lines, fr.phi_lo, pi / 2, gap)}, options);
}

Job hemisphere_job(std::function<double(const Vec3&)> F, std::vector<double> scales, double printed, double corrected,
                   bool at_horizon) {
  return [F = std::move(F), scales = std::move(scales), printed, corrected, at_horizon] {
    const Estimate e = integrate_over_lune(Vec3{0.0, 0.0, 1.0}, F, scales, at_horizon);
    return Sample{printed, corrected, e.value, e.error, e.converged, 1};
  };
}

CheckResult run_check(CheckResult check, const std::vector<Job>& jobs) {
  std::vector<Sample> samples(jobs.size());
  tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t k) { samples[k] = jobs[k](); });
  double worst = 0.0, worst_corrected = 0.0;
  bool has_corrected = false;
  auto diff = [](double x, double y) {
    const double d = std::abs(x - y);
    return std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
  };
  for (const Sample& s : samples) {
    worst = std::max(worst, diff(s.printed, s.reference));
    if (!std::isnan(s.corrected)) {
      has_corrected = true;
      worst_corrected = std::max(worst_corrected, diff(s.corrected, s.reference));
    }
    check.points += s.points;
    check.max_reference_error = std::max(check.max_reference_error, s.reference_error);
    check.references_converged = check.references_converged && s.converged;
  }
  check.max_abs_error = worst;
  check.erratum = worst > kAgreement;
  if (check.erratum && has_corrected) check.corrected_max_abs_error = worst_corrected;
  if (!check.erratum) check.corrected.clear();
  return check;
}

}  // namespace verify_support

std::vector<CheckResult> run_verification() {
  std::vector<CheckResult> all;
  for (auto&& group : {lambert_checks(), minnaert_checks(), specular_checks(), backscatter_checks(),
                       perfect_backscatter_checks(), asperity_checks()})
    all.insert(all.end(), group.begin(), group.end());
  all.push_back(reciprocity_check());
  all.push_back(mixture_check());
  for (auto&& check : hvd_checks()) all.push_back(std::move(check));
  for (auto&& check : ggx_checks()) all.push_back(std::move(check));
  for (auto&& check : catalogue_checks()) all.push_back(std::move(check));
  return all;
}

bool verification_passed(const std::vector<CheckResult>& checks) {
  for (const auto& c : checks) {
    if (!(c.max_reference_error <= kReferenceResolution)) return false;
    if (!c.erratum) continue;
    if (!c.corrected_max_abs_error || !(*c.corrected_max_abs_error <= kAgreement)) return false;
  }
  return true;
}

nlohmann::ordered_json verify_json(const std::vector<CheckResult>& checks) {
  nlohmann::ordered_json doc;
  doc["checks"] = nlohmann::ordered_json::array();
  for (const auto& c : checks) {
    nlohmann::ordered_json item{{"id", c.id},
                                {"source", c.source},
                                {"status", c.erratum ? "erratum" : "matches"},
                                {"max_abs_error", c.max_abs_error}};
    item["corrected_max_abs_error"] =
        c.corrected_max_abs_error ? nlohmann::ordered_json(*c.corrected_max_abs_error) : nlohmann::ordered_json();
    item["points"] = c.points;
    item["models"] = c.models;
    item["printed"] = c.printed;
    if (c.erratum) item["corrected"] = c.corrected;
    item["max_reference_error"] = c.max_reference_error;
    item["references_converged"] = c.references_converged;
    doc["checks"].push_back(item);
  }
  doc["agreement"] = kAgreement;
  doc["passed"] = verification_passed(checks);
  return doc;
}

std::string errata_markdown(const std::vector<CheckResult>& checks, const std::string& command) {
  auto sci = [](double x) {
    std::ostringstream s;
    s.precision(2);
    s << std::scientific << x;
    return s.str();
  };
  std::ostringstream md;
  md << "<!-- Generated by `" << command << "`; do not edit by hand. -->\n"
     << "# Errata and verification of the printed closed forms\n\n"
     << "Every closed form printed in Koenderink & Pont, *Material Properties and Extended Sources for Surface "
        "Rendering*, is compared with ganzfeld's adaptive cubature (absolute tolerance "
     << sci(kReferenceTolerance)
     << ") on a grid that includes the extremes: sky pole i·n ∈ {-1, -0.999, -0.7, -0.3, "
        "0, 1e-6, 0.3, 0.7, 0.999, 1}, view j·n ∈ {0, 1e-6, 0.25, 0.5, 0.75, 1}, relative azimuth ∈ {0°, 45°, 90°, "
        "135°, 180°} for g; i·n or j·n ∈ {0, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999, 1} for h and a. A form *matches* "
        "when its largest absolute difference is ≤ "
     << sci(kAgreement)
     << "; otherwise it is an *erratum*, and we derive, implement and check a corrected form. A reference that "
        "spends its budget before its tolerance is marked *not converged* with the error it states; it still "
        "classifies a form while that error is ≤ "
     << sci(kReferenceResolution) << ".\n\n"
     << "Regenerate with `" << command << "`.\n\n"
     << "| id | status | max abs error (printed) | max abs error (corrected) | points | max reference error estimate "
        "|\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& c : checks)
    md << "| `" << c.id << "` | " << (c.erratum ? "**erratum**" : "matches") << " | " << sci(c.max_abs_error) << " | "
       << (c.corrected_max_abs_error ? sci(*c.corrected_max_abs_error) : "—") << " | " << c.points << " | "
       << sci(c.max_reference_error) << (c.references_converged ? "" : " (not converged)") << " |\n";
  md << "\n## Errata\n";
  for (const auto& c : checks) {
    if (!c.erratum) continue;
    md << "\n### `" << c.id << "`\n\n"
       << "- Source: " << c.source << "\n"
       << "- Checked on: " << c.models << "\n"
       << "- Printed: `" << c.printed << "` — max abs error " << sci(c.max_abs_error) << "\n"
       << "- Corrected: `" << c.corrected << "` — max abs error "
       << (c.corrected_max_abs_error ? sci(*c.corrected_max_abs_error) : std::string("none")) << "\n\n"
       << c.explanation << "\n";
  }
  md << "\n## Claims that hold\n\n";
  for (const auto& c : checks)
    if (!c.erratum) md << "- `" << c.id << "` (" << c.models << "): " << c.printed << "\n";
  return md.str();
}

}  // namespace ganzfeld
