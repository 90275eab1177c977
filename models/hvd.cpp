// The halfway-vector-disk BRDFs of Edwards et al. (models/hvd.h), and their registration.
//
// hvd-empirical parameters (eq. 32–33):
//   cd   real [0,1]     0.5   diffuse colour C_d (scalar; colour is per lobe in the renderer)
//   f0   real [0,1]     0.04  Schlick F_0 (eq. 30)
//   eta  real [0,100]   0     refractive index; when > 0, F_0 = ((η−1)/(η+1))² (eq. 31) replaces f0
//   k    real [0,1]     0     weight of the retro-reflective lump
//   ns   real [0,1e6]   100   specular lump exponent n_s
//   nr   real [0,1e6]   10    retro-reflective lump exponent n_r
//   rs   real [1e-3,1]  1     specular radius as a fraction of its largest value 1 − sin θ_o
//   rr   real [1e-3,1]  1     retro-reflective radius R_r (its largest value is 1)
//   rsu, rsv, rru, rrv  real [0,1]  0  per-axis (u = +x, v = +y) radii, same units; 0 = use rs / rr
// hvd-fit parameters (eq. 34–36): cd, f0, f90, k, n1, r1, n2, r2 (radii absolute, unconstrained).
#include "models/hvd.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {

using std::numbers::pi;

namespace hvd {

double Lump::pdf(const Uv& h) const noexcept {
  const double du = (h.u - centre.u) / R_u, dv = (h.v - centre.v) / R_v;
  const double s = 1.0 - du * du - dv * dv;
  if (!(s > 0.0)) return 0.0;
  return (n + 1.0) / (pi * R_u * R_v) * std::pow(s, n);
}

Uv Lump::sample(double xi1, double xi2) const noexcept {
  // Eq. 28: 1 − ξ^(1/(n+1)) as −expm1(log ξ/(n+1)), exact for the large n of sharp lumps.
  const double s = xi1 > 0.0 ? -std::expm1(std::log(xi1) / (n + 1.0)) : 1.0;
  const double r = std::sqrt(std::clamp(s, 0.0, 1.0));
  const double theta = 2.0 * pi * xi2;
  return {centre.u + R_u * r * std::cos(theta), centre.v + R_v * r * std::sin(theta)};
}

std::optional<Vec3> incident_from_scaling(const Uv& h, const Vec3& j) noexcept {
  const Vec3 H = glm::normalize(Vec3{h.u, h.v, j.z});
  const Vec3 i = 2.0 * glm::dot(j, H) * H - j;
  if (!(i.z > 0.0)) return std::nullopt;
  return glm::normalize(i);
}

std::optional<Vec3> incident_from_orthogonal(const Uv& h, const Vec3& j) noexcept {
  const double x = h.u - j.x, y = h.v - j.y;
  const double s2 = x * x + y * y;
  if (!(s2 < 1.0)) return std::nullopt;
  return Vec3{x, y, std::sqrt(1.0 - s2)};
}

double schlick(double cos_theta, double F_0, double F_90) noexcept {
  const double x = 1.0 - std::clamp(cos_theta, 0.0, 1.0);
  const double x2 = x * x;
  return F_0 + (F_90 - F_0) * x2 * x2 * x;
}

double f0_from_eta(double eta) noexcept {
  const double r = (eta - 1.0) / (eta + 1.0);
  return r * r;
}

double max_specular_radius(double cos_theta_o) noexcept {
  const double c = std::clamp(cos_theta_o, 0.0, 1.0);
  return c * c / (1.0 + std::sqrt(1.0 - c * c));
}

Uv scaling_uv(const Vec3& i, const Vec3& j) noexcept {
  const Vec3 H = i + j;
  const double s = j.z / H.z;
  return {s * H.x, s * H.y};
}

Uv orthogonal_uv(const Vec3& i, const Vec3& j) noexcept { return {i.x + j.x, i.y + j.y}; }

// Eq. 8 and 19: Q = q / (4 ω_i·Ĥ), q = p dμ/dΩ(Ĥ) = p (ω_o·N)²/(Ĥ·N)³. With ω_i·Ĥ = |H|/2 and
// Ĥ·N = H_z/|H|: Q = p (ω_o·N)² |H|³ / (2 |H| H_z³) = p (ω_o·N)² |H|² / (2 H_z³).
double scaling_jacobian(const Vec3& i, const Vec3& j) noexcept {
  const Vec3 H = i + j;
  if (!(H.z > 0.0)) return 0.0;
  return j.z * j.z * glm::dot(H, H) / (2.0 * H.z * H.z * H.z);
}

}  // namespace hvd

namespace {

/// f = Q / (i·n), finite at the horizon (where the limit may be +inf for n = 0 lumps).
double divide_by_cos(double Q, double cos_i) noexcept {
  if (Q <= 0.0) return 0.0;
  const double f = Q / std::max(cos_i, std::numeric_limits<double>::min());
  return std::min(f, std::numeric_limits<double>::max());
}

/// Angular half-width of a lump's image in ω_i: the uv scale R/√(n+1) (the lump is ~
/// exp(−n r²/R²)), divided by the disk's height (angle of Ĥ) and doubled (reflection).
double lobe_width(double R, double n, double height) {
  const double sigma = 0.25 * R / std::sqrt(n + 1.0);
  return std::min(pi, 2.0 * sigma / std::max(height, 1e-300));
}

std::string num(double x) { return format_number(x); }

/// The scaling projection's layer is declared below this height only: it is thin at grazing, and
/// well below hint_rules::kThinLayer, where the engine starts to use a layer.
constexpr double kScalingLayerCeiling = 0.05;

}  // namespace

// ---------------------------------------------------------------------------------------------
std::array<hvd::Lump, 2> HvdEmpirical::lumps(const Vec3& j) const noexcept {
  const double R_max = hvd::max_specular_radius(j.z);
  hvd::Lump s{{0.0, 0.0}, p_.rs_u * R_max, p_.rs_v * R_max, p_.n_s};
  hvd::Lump r{{j.x, j.y}, p_.rr_u, p_.rr_v, p_.n_r};
  return {s, r};
}

double HvdEmpirical::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double F = hvd::schlick(j.z, p_.F_0);
  const double diffuse = (1.0 - F) * p_.C_d / pi;
  // At j·n = 0 the disk collapses to a point (R_s = 0): the specular part is a delta, 0 pointwise.
  if (!(j.z > 0.0)) return diffuse;
  const double J = hvd::scaling_jacobian(i, j);
  if (!(J > 0.0)) return diffuse;
  const hvd::Uv h = hvd::scaling_uv(i, j);
  const auto L = lumps(j);
  const double p = (1.0 - p_.k) * (p_.k < 1.0 ? L[0].pdf(h) : 0.0) + p_.k * (p_.k > 0.0 ? L[1].pdf(h) : 0.0);
  return diffuse + F * divide_by_cos(p * J, i.z);
}

std::optional<GlslF> HvdEmpirical::glsl_f() const {
  // As f: the lumps of eq. 32 placed for j (R_s = rs (1 - sin theta_o) = rs cos^2/(1 + sin), sin
  // theta_o = |j_xy|), the scaling projection and its Jacobian (hvd::scaling_uv, scaling_jacobian).
  std::string lumps;
  if (p_.k < 1.0)
    lumps += decimal_literal(1.0 - p_.k) + " * gz_hvd_lump(h, vec2(0.0), vec2(" + decimal_literal(p_.rs_u) + ", " +
             decimal_literal(p_.rs_v) + ") * R_max, " + decimal_literal(p_.n_s) + ")";
  if (p_.k > 0.0)
    lumps += std::string(lumps.empty() ? "" : " + ") + decimal_literal(p_.k) + " * gz_hvd_lump(h, j.xy, vec2(" +
             decimal_literal(p_.rr_u) + ", " + decimal_literal(p_.rr_v) + "), " + decimal_literal(p_.n_r) + ")";
  return GlslF{std::string(kGlslBelowHorizon) + "  float F = gz_schlick(j.z, " + decimal_literal(p_.F_0) +
                   ", 1.0);\n"
                   "  float diffuse = gz_one_minus_schlick(j.z, " +
                   decimal_literal(p_.F_0) + ", 1.0) * " + decimal_literal(p_.C_d / pi) +
                   ";\n"
                   "  if (!(j.z > 0.0)) return diffuse;\n"
                   "  vec3 H = i + j;\n"
                   "  if (!(H.z > 0.0)) return diffuse;\n"
                   "  float J = j.z * j.z * dot(H, H) / (2.0 * H.z * H.z * H.z);\n"
                   "  if (!(J > 0.0)) return diffuse;\n"
                   "  vec2 h = (j.z / H.z) * H.xy;\n"
                   "  float R_max = j.z * j.z / (1.0 + length(j.xy));\n"
                   "  float Q = (" +
                   lumps +
                   ") * J;\n"
                   "  if (!(Q > 0.0)) return diffuse;\n"
                   "  return diffuse + F * min(Q / max(i.z, 1.17549435e-38), 3.40282347e38);\n",
               {"gz_schlick", "gz_one_minus_schlick", "gz_hvd_lump"}};
}

namespace {
/// Probability of drawing the diffuse part: its share of ∫ f (i·n) di.
double diffuse_share(double diffuse, double specular) {
  return diffuse + specular > 0.0 ? diffuse / (diffuse + specular) : 1.0;
}
/// Picks the diffuse part (cosine) or a lump from u[0]; `lump_sample` maps a lump point to i.
template <class ToIncident>
std::optional<IncidentSample> sample_hvd(const Model& model, const Vec3& j, const std::array<double, 3>& u,
                                         double p_diffuse, const std::array<hvd::Lump, 2>& L, double k,
                                         ToIncident to_incident) {
  if (!(j.z > 0.0)) return std::nullopt;
  std::optional<Vec3> i;
  if (u[0] < p_diffuse) {
    i = sample_cosine(u[1], u[2]);
  } else {
    const double v = (u[0] - p_diffuse) / (1.0 - p_diffuse);  // uniform in [0, 1) again
    i = to_incident(L[v < 1.0 - k ? 0 : 1].sample(u[1], u[2]));
  }
  if (!i || !(i->z > 0.0)) return std::nullopt;
  const double pdf = model.pdf_incident(j, *i);
  if (!(pdf > 0.0)) return std::nullopt;
  return IncidentSample{*i, pdf};
}
}  // namespace

std::optional<IncidentSample> HvdEmpirical::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  const double F = hvd::schlick(j.z, p_.F_0);
  return sample_hvd(*this, j, u, diffuse_share((1.0 - F) * p_.C_d, F), lumps(j), p_.k,
                    [&](const hvd::Uv& h) { return hvd::incident_from_scaling(h, j); });
}

double HvdEmpirical::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const double F = hvd::schlick(j.z, p_.F_0);
  const double P_d = diffuse_share((1.0 - F) * p_.C_d, F);
  double lump = 0.0;
  if (P_d < 1.0) {
    const double J = hvd::scaling_jacobian(i, j);
    if (J > 0.0) {
      const auto L = lumps(j);
      const hvd::Uv h = hvd::scaling_uv(i, j);
      lump = ((1.0 - p_.k) * (p_.k < 1.0 ? L[0].pdf(h) : 0.0) + p_.k * (p_.k > 0.0 ? L[1].pdf(h) : 0.0)) * J;
    }
  }
  return P_d * i.z / pi + (1.0 - P_d) * lump;
}

MassHints HvdEmpirical::mass_hints(const Vec3& fixed, Varying) const {
  // The specular lump's centre maps to Ĥ = n, i.e. the mirror direction; the retro lump's centre
  // to Ĥ = ω_o, i.e. back to the fixed direction. Used for albedo too (fixed = i): the lobes
  // in ω_o then sit near the same directions.
  HintBuilder hints;
  const double height = std::max(fixed.z, 0.0);
  // Anisotropic lumps: one peak per axis, so the initial grid resolves both scales.
  const double R_max = hvd::max_specular_radius(height);
  const double w_s = lobe_width(std::min(p_.rs_u, p_.rs_v) * R_max, p_.n_s, height);
  const double w_s_wide = lobe_width(std::max(p_.rs_u, p_.rs_v) * R_max, p_.n_s, height);
  // Across the plane of incidence a disk offset dv moves i by 2 dv whatever the height (i =
  // 2(j·Ĥ)Ĥ − j with Ĥ tilted by dv/(j·n) and j·Ĥ ~ j·n), while along it i moves by 2 du/(j·n):
  // near grazing the lobe is a thin arc, 1/(j·n) times thinner across than along.
  const double across_s = lobe_width(std::min(p_.rs_u, p_.rs_v) * R_max, p_.n_s, 1.0);
  if (p_.k < 1.0) {
    hints.lobe(mirror(fixed), w_s, across_s);
    if (w_s_wide > w_s) hints.lobe(mirror(fixed), w_s_wide, across_s);
  }
  if (p_.k > 0.0) {
    hints.lobe(fixed, lobe_width(std::min(p_.rr_u, p_.rr_v), p_.n_r, 1.0));
    if (p_.rr_u != p_.rr_v) hints.lobe(fixed, lobe_width(std::max(p_.rr_u, p_.rr_v), p_.n_r, 1.0));
  }
  // Towards grazing the specular lobe hugs the horizon.
  if (p_.k < 1.0) hints.layer_where_lobe_meets_horizon(height, w_s);
  // The scaling projection's Jacobian j_z² |H|²/(2 H_z³) and its uv = (j_z/H_z) H_xy change within
  // k·n ~ fixed·n of the horizon (H_z = k_z + fixed_z): a layer of that thickness holding O(1) of
  // either lump's mass, whatever k, retro only (k = 1) included (tests/extremes_test.cpp,
  // HvdScalingLayerIsHonest).
  if (height < kScalingLayerCeiling) hints.layer(height);
  return hints.build();
}

std::string HvdEmpirical::spec() const {
  ModelSpec spec{"hvd-empirical", {{"cd", p_.C_d}, {"k", p_.k}, {"ns", p_.n_s}, {"nr", p_.n_r}}};
  if (p_.eta > 0.0) spec.values["eta"] = p_.eta;
  else spec.values["f0"] = p_.F_0;
  if (p_.rs_u == p_.rs_v) spec.values["rs"] = p_.rs_u;
  else spec.values.insert({{"rsu", p_.rs_u}, {"rsv", p_.rs_v}});
  if (p_.rr_u == p_.rr_v) spec.values["rr"] = p_.rr_u;
  else spec.values.insert({{"rru", p_.rr_u}, {"rrv", p_.rr_v}});
  return spec_text(spec);
}

Traits HvdEmpirical::traits() const {
  // Conserving over incident directions (h = 1 for C_d = 1), but not reciprocal, so a != h:
  // K&P's constraint of reciprocity fails, hence "not plausible" (measured by `verify`).
  return {p_.rs_u == p_.rs_v && p_.rr_u == p_.rr_v, false, EnergyClass::not_plausible};
}

// ---------------------------------------------------------------------------------------------
std::array<hvd::Lump, 2> HvdFit::lumps() const noexcept {
  return {hvd::Lump{{0.0, 0.0}, p_.R_1, p_.R_1, p_.n_1}, hvd::Lump{{0.0, 0.0}, p_.R_2, p_.R_2, p_.n_2}};
}

double HvdFit::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double F = hvd::schlick(j.z, p_.F_0, p_.F_90);
  const hvd::Uv h = hvd::orthogonal_uv(i, j);
  const auto L = lumps();
  // Eq. 24 reduces to ρ_s = p(h) because |ω_i + ω_o|² = 4 (ω_i·Ĥ)².
  const double p = (1.0 - p_.k) * L[0].pdf(h) + p_.k * L[1].pdf(h);
  return (1.0 - F) * p_.C_d / pi + F * p;
}

std::optional<GlslF> HvdFit::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + "  float F = gz_schlick(j.z, " + decimal_literal(p_.F_0) + ", " +
                   decimal_literal(p_.F_90) +
                   ");\n"
                   "  vec2 h = i.xy + j.xy;\n"
                   "  float p = " +
                   decimal_literal(1.0 - p_.k) + " * gz_hvd_lump(h, vec2(0.0), vec2(" + decimal_literal(p_.R_1) +
                   "), " + decimal_literal(p_.n_1) + ") + " + decimal_literal(p_.k) +
                   " * gz_hvd_lump(h, vec2(0.0), vec2(" + decimal_literal(p_.R_2) + "), " + decimal_literal(p_.n_2) +
                   ");\n"
                   "  return gz_one_minus_schlick(j.z, " +
                   decimal_literal(p_.F_0) + ", " + decimal_literal(p_.F_90) + ") * " + decimal_literal(p_.C_d / pi) +
                   " + F * p;\n",
               {"gz_schlick", "gz_one_minus_schlick", "gz_hvd_lump"}};
}

std::optional<IncidentSample> HvdFit::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  const double F = hvd::schlick(j.z, p_.F_0, p_.F_90);
  return sample_hvd(*this, j, u, diffuse_share((1.0 - F) * p_.C_d, F), lumps(), p_.k,
                    [&](const hvd::Uv& h) { return hvd::incident_from_orthogonal(h, j); });
}

double HvdFit::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const double F = hvd::schlick(j.z, p_.F_0, p_.F_90);
  const double P_d = diffuse_share((1.0 - F) * p_.C_d, F);
  const auto L = lumps();
  const hvd::Uv h = hvd::orthogonal_uv(i, j);
  // dA = (i·n) dω_i on the disk (eq. 23 with |H|² = 4(ω_i·Ĥ)²).
  const double lump = ((1.0 - p_.k) * L[0].pdf(h) + p_.k * L[1].pdf(h)) * i.z;
  return P_d * i.z / pi + (1.0 - P_d) * lump;
}

MassHints HvdFit::mass_hints(const Vec3& fixed, Varying) const {
  // h = i_uv + j_uv = 0 at the mirror direction; ρ cos dω = p dA, and dA = cos dω, so the lobe's
  // angular width about the mirror direction is ~ R/√(n+1) / cos θ near grazing.
  HintBuilder hints;
  const double height = std::max(fixed.z, 1e-300);
  const double w1 = std::min(pi, p_.R_1 / std::sqrt(p_.n_1 + 1.0) / std::sqrt(height));
  const double w2 = std::min(pi, p_.R_2 / std::sqrt(p_.n_2 + 1.0) / std::sqrt(height));
  // Across the plane of incidence a disk offset moves i by the same angle whatever the height.
  if (p_.k < 1.0) hints.lobe(mirror(fixed), w1, std::min(pi, p_.R_1 / std::sqrt(p_.n_1 + 1.0)));
  if (p_.k > 0.0) hints.lobe(mirror(fixed), w2, std::min(pi, p_.R_2 / std::sqrt(p_.n_2 + 1.0)));
  return hints.layer_where_lobe_meets_horizon(fixed.z, std::min(w1, w2)).build();
}

std::string HvdFit::spec() const {
  return spec_text({"hvd-fit",
                    {{"cd", p_.C_d},
                     {"f0", p_.F_0},
                     {"f90", p_.F_90},
                     {"k", p_.k},
                     {"n1", p_.n_1},
                     {"r1", p_.R_1},
                     {"n2", p_.n_2},
                     {"r2", p_.R_2}}});
}

Traits HvdFit::traits() const { return {true, false, EnergyClass::not_plausible}; }

// ---------------------------------------------------------------------------------------------
namespace {

const char* kEdwards = "Edwards et al. 2006, \"The Halfway Vector Disk for BRDF Modeling\"";

HvdEmpirical::Params empirical_params(const ParamValues& v) {
  HvdEmpirical::Params p;
  p.C_d = v.at("cd");
  p.eta = v.at("eta");
  if (p.eta > 0.0) {
    // A given f0 that disagrees with eta is a contradiction (f0's default is left alone).
    const double from_eta = hvd::f0_from_eta(p.eta);
    if (v.at("f0") != 0.04 && std::abs(v.at("f0") - from_eta) > 1e-12)
      throw InputError("hvd-empirical: f0=" + num(v.at("f0")) + " contradicts eta=" + num(p.eta) +
                       " (eq. 31 gives f0=" + num(from_eta) + "); allowed: give one of f0, eta");
    p.F_0 = from_eta;
  } else {
    p.F_0 = v.at("f0");
  }
  p.k = v.at("k");
  p.n_s = v.at("ns");
  p.n_r = v.at("nr");
  auto radius = [&](const char* axis, const char* base) {
    const double r = v.at(axis);
    return r > 0.0 ? r : v.at(base);
  };
  p.rs_u = radius("rsu", "rs");
  p.rs_v = radius("rsv", "rs");
  p.rr_u = radius("rru", "rr");
  p.rr_v = radius("rrv", "rr");
  return p;
}

}  // namespace

void register_hvd_models(std::vector<ModelInfo>& catalogue) {
  using P = ParamType;
  const auto radius_axis = [](const char* name, const char* meaning, const char* radius) {
    return ParamInfo{.name = name,
                     .type = P::real,
                     .min = 0.0,
                     .max = 1.0,
                     .default_value = 0.0,
                     .meaning = meaning,
                     .alternative_of = radius};
  };
  const std::string radius_note =
      " (fraction of the largest radius keeping the lump on the disk; > 1 would lose energy)";
  catalogue.push_back(
      {"hvd-empirical",
       "energy-conserving halfway-vector-disk BRDF: (1-F) C_d/pi + F x (specular + retro lumps), scaling projection",
       std::string(kEdwards) + ", section 4, eq. 32-33",
       {{"cd", P::real, 0.0, 1.0, 0.5, "diffuse colour C_d"},
        {"f0", P::real, 0.0, 1.0, 0.04, "Schlick F_0, reflectance at normal incidence (eq. 30)"},
        {.name = "eta",
         .type = P::real,
         .min = 0.0,
         .max = 100.0,
         .default_value = 0.0,
         .meaning = "refractive index; > 0 sets F_0 = ((eta-1)/(eta+1))^2 (eq. 31); 0 = use f0",
         .alternative_of = "f0"},
        {"k", P::real, 0.0, 1.0, 0.0, "weight of the retro-reflective lump (0 = specular only)"},
        {"ns", P::real, 0.0, 1e6, 100.0, "specular lump exponent n_s (0 = uniform)"},
        {"nr", P::real, 0.0, 1e6, 10.0, "retro-reflective lump exponent n_r"},
        {"rs", P::real, 1e-3, 1.0, 1.0, "specular radius R_s / (1 - sin theta_o)" + radius_note},
        {"rr", P::real, 1e-3, 1.0, 1.0, "retro-reflective radius R_r" + radius_note},
        radius_axis("rsu", "specular radius along u = +x, as rs (0 = rs)", "rs"),
        radius_axis("rsv", "specular radius along v = +y, as rs (0 = rs)", "rs"),
        radius_axis("rru", "retro-reflective radius along u = +x, as rr (0 = rr)", "rr"),
        radius_axis("rrv", "retro-reflective radius along v = +y, as rr (0 = rr)", "rr")},
       {true, false, EnergyClass::not_plausible},
       {"hvd.lump.volume", "hvd.energy.scaling", "hvd.reciprocity"},
       [](const ParamValues& v) -> ModelPtr {
         for (const char* axis : {"rsu", "rsv", "rru", "rrv"})
           if (v.at(axis) > 0.0 && v.at(axis) < 1e-3)
             throw InputError(std::string("hvd-empirical: ") + axis + "=" + num(v.at(axis)) +
                              " is out of range; allowed: 0 (inherit) or a real number in [0.001, 1]");
         return std::make_shared<HvdEmpirical>(empirical_params(v));
       }});
  catalogue.push_back(
      {"hvd-fit",
       "data-fitting halfway-vector-disk BRDF: (1-F_fit) C_d/pi + F_fit x two lumps at the origin, orthogonal "
       "projection; "
       "loses energy where the lumps leave the disk",
       std::string(kEdwards) + ", section 5, eq. 34-36",
       {{"cd", P::real, 0.0, 1.0, 0.5, "diffuse colour C_d"},
        {"f0", P::real, 0.0, 1.0, 0.04, "F_0, reflectance at normal incidence (eq. 34)"},
        {"f90", P::real, 0.0, 1.0, 1.0, "F_pi/2, reflectance at grazing (eq. 34)"},
        {"k", P::real, 0.0, 1.0, 0.0, "weight of the second lump"},
        {"n1", P::real, 0.0, 1e6, 100.0, "first lump exponent"},
        {"r1", P::real, 1e-6, 100.0, 0.2, "first lump radius (absolute, not constrained to the disk)"},
        {"n2", P::real, 0.0, 1e6, 10.0, "second lump exponent"},
        {"r2", P::real, 1e-6, 100.0, 0.5, "second lump radius (absolute, not constrained to the disk)"}},
       {true, false, EnergyClass::not_plausible},
       {"hvd.lump.volume", "hvd.energy.orthogonal"},
       [](const ParamValues& v) -> ModelPtr {
         HvdFit::Params p;
         p.C_d = v.at("cd");
         p.F_0 = v.at("f0");
         p.F_90 = v.at("f90");
         p.k = v.at("k");
         p.n_1 = v.at("n1");
         p.R_1 = v.at("r1");
         p.n_2 = v.at("n2");
         p.R_2 = v.at("r2");
         return std::make_shared<HvdFit>(p);
       }});
}

}  // namespace ganzfeld
