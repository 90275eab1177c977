// `ganzfeld verify` checks of the catalogue's other printed forms:
//   ashikhmin-shirley.pdf      Ashikhmin & Shirley 2000: the density of their halfway-vector draw,
//                              p_h = sqrt((n_u + 1)(n_v + 1))/(2 pi) (h·n)^(n_u cos^2 phi + n_v sin^2 phi),
//                              integrates to 1 over the hemisphere
//   ashikhmin-shirley.diffuse  their diffuse term's constant 28/(23 pi): the albedo of rho_d is
//                              R_d (1 - R_s)(1 - (1 - (i·n)/2)^5)
//   schlick.z.norm             Schlick 1994: the normalization of a slope distribution,
//                              ∫∫ D cos alpha sin alpha d alpha d phi = pi, for Z(t) = r/(1 + r t^2 - t^2)^2
//   schlick.a.norm             the same for Z(t) A(w) with the printed A = sqrt(p/(p^2 - p^2 w^2 + w^2)):
//                              holds only at p = 1; corrected with A's mean (models/schlick.h)
//   kajiya.cylinder            Kajiya & Kay 1989, section 3.3: a Lambertian cylinder of radius 1 lit
//                              from l intercepts ∫ max(0, N(psi)·l) d psi = 2 sin(t, l) around its axis t
// Integrals over the hemisphere run on the lune with pole n (reports/verify_support.h); the
// cylinder's around the circle, split where N(psi)·l changes sign.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "integrate/laws.h"
#include "models/ashikhmin_shirley.h"
#include "models/registry.h"
#include "models/schlick.h"
#include "models/spec.h"
#include "reports/verify.h"
#include "reports/verify_support.h"

namespace ganzfeld {

namespace {

using std::numbers::pi;
using namespace verify_support;

const char* kAshikhminShirley = "Ashikhmin & Shirley 2000, An Anisotropic Phong BRDF Model, JGT 5(2)";
const char* kSchlick = "Schlick 1994, An Inexpensive BRDF Model for Physically-based Rendering, CGF 13(3)";

struct Exponents {
  double nu, nv;
};

CheckResult as_pdf_check() {
  const std::vector<Exponents> cases{{0, 0},       {1, 1},     {10, 10},   {100, 100},
                                     {1000, 1000}, {10, 1000}, {0, 10000}, {10000, 10000}};
  std::vector<Job> jobs;
  std::string models;
  for (const Exponents& e : cases) {
    const AshikhminShirley model(0.5, 0.05, e.nu, e.nv);
    append_model(models, model.spec());
    const double narrow = 1.0 / std::sqrt(std::max(e.nu, e.nv) + 1.0);
    const double wide = 1.0 / std::sqrt(std::min(e.nu, e.nv) + 1.0);
    jobs.push_back(
        hemisphere_job([model](const Vec3& h) { return model.halfway_pdf(h); }, {narrow / 4, wide / 4}, 1.0));
  }
  return run_check(
      check_meta("ashikhmin-shirley.pdf", std::string(kAshikhminShirley) + ", Monte Carlo sampling", models,
                 "the halfway vectors drawn by phi = atan(sqrt((n_u+1)/(n_v+1)) tan(pi xi_1/2)), "
                 "cos theta = (1 - xi_2)^(1/(n_u cos^2 phi + n_v sin^2 phi + 1)) have the density "
                 "p_h(h) = sqrt((n_u+1)(n_v+1))/(2 pi) (h.n)^(n_u cos^2 phi + n_v sin^2 phi), which "
                 "integrates to 1 over the hemisphere"),
      jobs);
}

CheckResult as_diffuse_check() {
  std::vector<Job> jobs;
  const std::vector<double> rs_values{0.0, 0.05, 0.5};
  std::string models;
  for (double rs : rs_values) {
    const AshikhminShirley model(1.0, rs, 10.0, 10.0);
    append_model(models, model.spec());
    for (double mu : {1.0, 0.9, 0.5, 0.1, 1e-3, 0.0}) {
      const Vec3 i = direction_from_cos(mu);
      const double x = 1.0 - 0.5 * mu;
      jobs.push_back(hemisphere_job([model, i](const Vec3& k) { return model.diffuse(i, k) * k.z; }, {1.0},
                                    (1.0 - rs) * (1.0 - x * x * x * x * x)));
    }
  }
  return run_check(
      check_meta("ashikhmin-shirley.diffuse", std::string(kAshikhminShirley) + ", the diffuse term", models,
                 "rho_d = 28 R_d/(23 pi) (1 - R_s)(1 - (1 - i.n/2)^5)(1 - (1 - j.n/2)^5) reflects "
                 "R_d (1 - R_s)(1 - (1 - i.n/2)^5) of the light from i: 28/(23 pi) is 1/(2 pi "
                 "integral_0^1 (1 - (1 - mu/2)^5) mu d mu) (R_d = 1, i.n = 1 ... 0)"),
      jobs);
}

CheckResult schlick_z_check() {
  std::vector<Job> jobs;
  const std::vector<double> roughness{1.0, 0.5, 0.1, 0.01, 1e-3};
  std::string models;
  for (double r : roughness) {
    append_model(models, spec_text({"schlick", {{"r", r}}}));
    jobs.push_back(
        hemisphere_job([r](const Vec3& h) { return schlick::zenith(h.z, r) * h.z; }, {std::sqrt(r) / 4}, pi));
  }
  return run_check(check_meta("schlick.z.norm", std::string(kSchlick) + ", the normalization of D and Z(t)", models,
                              "a slope distribution satisfies integral integral D(alpha, phi) cos alpha sin alpha "
                              "d alpha d phi = pi; Z(t) = r/(1 + r t^2 - t^2)^2 (t = cos alpha) does"),
                   jobs);
}

CheckResult schlick_a_check() {
  std::vector<Job> jobs;
  const std::vector<double> isotropy{1.0, 0.5, 0.1, 0.01};
  constexpr double kRoughness = 0.1;
  std::string models;
  for (double p : isotropy) {
    append_model(models, spec_text({"schlick", {{"r", kRoughness}, {"p", p}}}));
    const auto D = [p](const Vec3& h) {
      const double s = std::hypot(h.x, h.y), w = s > 0.0 ? h.x / s : 1.0;
      return schlick::zenith(h.z, kRoughness) * schlick::azimuth(w, p) * h.z;
    };
    jobs.push_back(hemisphere_job(D, {std::min(p, std::sqrt(kRoughness)) / 4, std::sqrt(kRoughness) / 4}, pi,
                                  pi * schlick::azimuth_mean(p)));
  }
  return run_check(
      check_meta("schlick.a.norm", std::string(kSchlick) + ", the anisotropic distribution Z(t) A(w)", models,
                 "integral integral Z(t) A(w) cos alpha sin alpha d alpha d phi = pi with A(w) = "
                 "sqrt(p/(p^2 - p^2 w^2 + w^2)), w = cos phi (the normalization of a slope distribution)",
                 "the integral is pi a(p), a(p) = (2/pi) sqrt(p) K(sqrt(1 - p^2)) the mean of A over phi (K the "
                 "complete elliptic integral of the first kind); the model uses A/a(p)",
                 "Z carries the whole normalization; A multiplies it by its mean over the azimuth, "
                 "(1/(2 pi)) integral_0^(2 pi) sqrt(p)/sqrt(cos^2 phi + p^2 sin^2 phi) d phi = (2/pi) sqrt(p) "
                 "K(sqrt(1 - p^2)), which is 1 only at p = 1 (0.971 at p = 0.5, 0.744 at 0.1, 0.381 at 0.01): "
                 "the printed anisotropic distribution loses that fraction of its energy"),
      jobs);
}

CheckResult kajiya_cylinder_check() {
  std::vector<Job> jobs;
  std::string models = "kajiya (the diffuse term's sin(t, l))";
  for (double theta_t : {0.0, 10.0, 45.0, 80.0, 90.0})
    for (double phi : {0.0, 30.0, 90.0}) {
      // l at angle theta_t from the axis t = x, turned by phi about it.
      const double a = theta_t * pi / 180.0, b = phi * pi / 180.0;
      const Vec3 l{std::cos(a), std::sin(a) * std::sin(b), std::sin(a) * std::cos(b)};
      jobs.push_back([l] {
        // N(psi) = (0, sin psi, cos psi); N·l = l_y sin psi + l_z cos psi = R cos(psi - psi_0) >= 0
        // on [psi_0 - pi/2, psi_0 + pi/2]: those are the cuts.
        const double psi_0 = std::atan2(l.y, l.z);
        std::vector<double> lines{-pi, pi};
        for (double c : {psi_0 - pi / 2, psi_0 + pi / 2, psi_0 - 1.5 * pi, psi_0 + 1.5 * pi})
          if (c > -pi && c < pi) lines.push_back(c);
        const auto integrand =
            pointwise<1>([&](double x) { return std::max(0.0, l.y * std::sin(x) + l.z * std::cos(x)); });
        const Estimate e = adaptive_cubature<1>(integrand, {tidy_cuts(lines, -pi, pi, 1e-12)}, reference_options());
        return Sample{2.0 * std::hypot(l.y, l.z), kNaN, e.value, e.error, e.converged, 1};
      });
    }
  return run_check(
      check_meta("kajiya.cylinder",
                 "Kajiya & Kay 1989, Rendering Fur with Three Dimensional Textures, section 3.3 (diffuse)", models,
                 "a Lambertian cylinder of unit radius along t lit from l intercepts integral over its "
                 "circumference of max(0, N.l) = 2 sin(t, l): the diffuse term is proportional to "
                 "sin(t, l) (t.l = cos 0 ... 90 deg, three azimuths about t)"),
      jobs);
}

}  // namespace

std::vector<CheckResult> catalogue_checks() {
  return {as_pdf_check(), as_diffuse_check(), schlick_z_check(), schlick_a_check(), kajiya_cylinder_check()};
}

}  // namespace ganzfeld
