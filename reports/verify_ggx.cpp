// `ganzfeld verify` checks of the microfacet models (models/ggx.h, models/charlie.h).
//   ggx.norm          Walter eq. 33 / Heitz 2014: ∫ D(m)(m·n) dm = 1 (isotropic and anisotropic α)
//   ggx.g1            Walter eq. 34 / Heitz eq. 80, 86: G1 = 2/(1 + sqrt(1 + α_w² tan²θ)) is Smith's
//                     (w·n)/∫ max(0, w·m) D(m) dm, and equals our 1/(1 + Λ)
//   ggx.furnace.e11   the white furnace: E(μ = 1, α = 1) = 1 − ln 2 with F = 1, for both G2 forms
//   charlie.norm      Estevez & Kulla: ∫ D(m)(m·n) dm = 1
// The integrals over m run on the lune {m·n > 0, m·w > 0} of integrate/laws.h, so the kink of
// max(0, w·m) is an edge of the domain, with cut lines at the scale of the distribution's peak.
#include <cmath>
#include <functional>
#include <numbers>

#include "integrate/laws.h"
#include "models/charlie.h"
#include "models/ggx.h"
#include "models/registry.h"
#include "models/spec.h"
#include "reports/verify.h"
#include "reports/verify_support.h"

namespace ganzfeld {

namespace {

using std::numbers::pi;
using namespace verify_support;

struct AlphaCase {
  ggx::Alpha alpha;
  std::string text() const {
    return alpha.x == alpha.y ? "alpha=" + format_number(alpha.x)
                              : "alpha_x=" + format_number(alpha.x) + ",alpha_y=" + format_number(alpha.y);
  }
};

const std::vector<AlphaCase> kAlphas{{{1.0, 1.0}},     {{0.5, 0.5}},  {{0.1, 0.1}},  {{0.01, 0.01}},
                                     {{0.001, 0.001}}, {{0.05, 0.5}}, {{0.001, 1.0}}};

std::string alpha_list(const std::vector<AlphaCase>& cases) {
  std::string s;
  for (const auto& c : cases) s += (s.empty() ? "ggx:" : "; ggx:") + c.text();
  return s;
}

CheckResult norm_check() {
  std::vector<Job> jobs;
  for (const auto& c : kAlphas)
    jobs.push_back(hemisphere_job([c](const Vec3& m) { return ggx::D(m, c.alpha) * m.z; },
                                  {std::min(c.alpha.x, c.alpha.y) / 4, std::max(c.alpha.x, c.alpha.y) / 4}, 1.0));
  return run_check(
      check_meta("ggx.norm", "Walter et al. 2007, eq. 33; Heitz 2014, anisotropic GGX", alpha_list(kAlphas),
                 "the GGX distribution D = 1/(pi alpha_x alpha_y (m_x^2/alpha_x^2 + m_y^2/alpha_y^2 + m_z^2)^2) "
                 "is normalized, integral of D(m)(m.n) dm = 1"),
      jobs);
}

/// Walter eq. 34 with Heitz eq. 80's projected roughness α_w² = cos²φ α_x² + sin²φ α_y².
double g1_printed(const Vec3& w, ggx::Alpha a) {
  const double s2 = w.x * w.x + w.y * w.y;
  if (!(s2 > 0.0)) return 1.0;
  const double alpha_w2 = (w.x * w.x * a.x * a.x + w.y * w.y * a.y * a.y) / s2;
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha_w2 * s2 / (w.z * w.z)));
}

CheckResult g1_check() {
  std::vector<Job> jobs;
  const std::vector<AlphaCase> alphas{{{1.0, 1.0}}, {{0.3, 0.3}}, {{0.01, 0.01}}, {{0.05, 0.5}}};
  for (const auto& c : alphas)
    for (double theta : {0.0, 30.0, 60.0, 80.0, 89.0, 89.9})
      for (double phi : {0.0, 40.0}) {
        const Vec3 w = direction(theta * pi / 180.0, phi * pi / 180.0);
        // Smith: G1(w) = (w·n) / I, I = ∫ max(0, w·m) D(m) dm (the visible projected area of the
        // facets). I >= w·n, so I to (w·n) x tolerance gives G1 to G1² x tolerance.
        jobs.push_back([c, w] {
          CubatureOptions options = reference_options();
          options.abs_tol *= w.z;
          const Estimate e = integrate_over_lune(
              w, [&](const Vec3& m) { return glm::dot(w, m) * ggx::D(m, c.alpha); },
              {std::min(c.alpha.x, c.alpha.y) / 4, std::max(c.alpha.x, c.alpha.y) / 4}, false, options);
          const double G1 = w.z / e.value;
          return Sample{g1_printed(w, c.alpha), kNaN, G1, G1 * e.error / e.value, e.converged, 1};
        });
        jobs.push_back([c, w] {  // and our 1/(1 + Λ), Heitz eq. 86
          return Sample{g1_printed(w, c.alpha), kNaN, 1.0 / (1.0 + ggx::Lambda(w, c.alpha)), 0.0, true, 1};
        });
      }
  return run_check(
      check_meta("ggx.g1", "Walter et al. 2007, eq. 34; Heitz 2014, eq. 80 and 86", alpha_list(alphas),
                 "Smith's G1(w) = (w.n) / integral of max(0, w.m) D(m) dm equals 2/(1 + sqrt(1 + alpha_w^2 "
                 "tan^2 theta_w)), alpha_w^2 = cos^2 phi_w alpha_x^2 + sin^2 phi_w alpha_y^2, and 1/(1 + Lambda(w)) "
                 "(theta_w = 0 ... 89.9 deg, phi_w = 0, 40 deg)"),
      jobs);
}

CheckResult furnace_check() {
  std::vector<Job> jobs;
  const std::vector<std::string> specs{"ggx:alpha=1,f0=1,g2=height-correlated", "ggx:alpha=1,f0=1,g2=separable"};
  for (const auto& spec : specs)
    jobs.push_back([spec] {
      const Estimate e = albedo(*parse_model(spec), Vec3{0.0, 0.0, 1.0}, reference_options());
      return Sample{1.0 - std::log(2.0), kNaN, e.value, e.error, e.converged, 1};
    });
  return run_check(
      check_meta("ggx.furnace.e11", "white furnace", specs[0] + "; " + specs[1],
                 "E(mu = 1, alpha = 1) = integral of f(n, o)(o.n) do = 1 - ln 2 with F = 1: at i = n, Lambda(i) = 0, "
                 "so both G2 forms are G1(o) = 2 mu/(1 + mu); alpha = 1 makes D = 1/pi, and E = (1/(4 pi)) 2 pi "
                 "integral_0^1 2 mu/(1 + mu) d mu = 1 - ln 2"),
      jobs);
}

CheckResult charlie_norm_check() {
  std::vector<Job> jobs;
  const std::vector<double> alphas{1.0, 0.5, 0.1, 0.01};
  std::string models;
  for (double a : alphas) {
    append_model(models, "charlie:alpha=" + format_number(a));
    // Its mass lies within ~sqrt(alpha) of the horizon (sin^(1/alpha) ~ exp(-cos^2/(2 alpha))).
    const Charlie charlie(a);
    jobs.push_back(hemisphere_job([charlie](const Vec3& m) { return charlie.D(1.0 - m.z * m.z) * m.z; },
                                  {std::sqrt(a) / 4}, 1.0, kNaN, true));
  }
  return run_check(check_meta("charlie.norm", "Estevez & Kulla 2017, Production Friendly Microfacet Sheen BRDF", models,
                              "the sheen distribution D = (2 + 1/alpha) sin^(1/alpha)(theta)/(2 pi) is normalized, "
                              "integral of D(m)(m.n) dm = 1"),
                   jobs);
}

}  // namespace

std::vector<CheckResult> ggx_checks() { return {norm_check(), g1_check(), furnace_check(), charlie_norm_check()}; }

}  // namespace ganzfeld
