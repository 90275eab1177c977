// The GGX microfacet BRDF (models/ggx.h) and its registration.
//
// ggx parameters (one of alpha, roughness, or alpha_x with alpha_y; none: alpha = 0.5):
//   alpha      real (0,1]  GGX roughness α, the width of the distribution of facet normals
//   roughness  real (0,1]  perceptual roughness R, α = R² (the engines' convention)
//   alpha_x    real (0,1]  α along the tangent (local +x); with alpha_y: anisotropic
//   alpha_y    real (0,1]  α along the bitangent (local +y)
//   f0         real [0,1]  1   Schlick's reflectance at normal incidence (1: F = 1)
//   g2         choice      height-correlated | separable (Heitz 2014, section 6)
// α = 0 would be a mirror (a delta, no BRDF): refused, as is roughness = 0.
#include "models/ggx.h"
#include "models/ggx_ms.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "models/hvd.h"
#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {

using std::numbers::pi;

namespace ggx {

double D(const Vec3& m, Alpha a) noexcept {
  if (!(m.z > 0.0)) return 0.0;
  const double x = m.x / a.x, y = m.y / a.y;
  const double q = x * x + y * y + m.z * m.z;  // m_x, m_y directly: no 1 − m_z² cancellation near n
  return 1.0 / (pi * a.x * a.y * q * q);
}

double projected_root(const Vec3& w, Alpha a) noexcept {
  const double x = a.x * w.x, y = a.y * w.y;
  return std::sqrt(w.z * w.z + x * x + y * y);
}

double Lambda(const Vec3& w, Alpha a) noexcept {
  if (!(w.z > 0.0)) return std::numeric_limits<double>::infinity();
  // (w·n) Λ = (projected_root − w·n)/2: Heitz eq. 86 multiplied by cos θ_w.
  return 0.5 * (projected_root(w, a) - w.z) / w.z;
}

double G1(const Vec3& w, Alpha a) noexcept {
  if (!(w.z > 0.0)) return 0.0;
  return 2.0 * w.z / (w.z + projected_root(w, a));
}

double visibility(const Vec3& i, const Vec3& j, Alpha a, G2Form form) noexcept {
  const double r_i = projected_root(i, a), r_j = projected_root(j, a);
  // 4 (i·n)(j·n)(1 + Λ(i) + Λ(j)) = 2 (j·n) r_i + 2 (i·n) r_j, and
  // 4 (i·n)(j·n)/(G1(i) G1(j)) = ((i·n) + r_i)((j·n) + r_j): the cosines cancel exactly.
  const double den = form == G2Form::height_correlated ? 2.0 * (j.z * r_i + i.z * r_j) : (i.z + r_i) * (j.z + r_j);
  return den > 0.0 ? 1.0 / den : 0.0;
}

double D_visible(const Vec3& w, const Vec3& m, Alpha a) noexcept {
  const double wm = glm::dot(w, m);
  if (!(w.z > 0.0) || !(wm > 0.0)) return 0.0;
  return G1(w, a) * wm * D(m, a) / w.z;
}

Vec3 sample_visible_normal(const Vec3& w, Alpha a, double u1, double u2) noexcept {
  // Section 3.2: stretch w to the configuration where the visible facets form a hemisphere.
  const Vec3 v = glm::normalize(Vec3{a.x * w.x, a.y * w.y, w.z});
  // Section 4.1: an orthonormal basis about v (any, when v = n).
  const double len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0.0 ? Vec3{-v.y, v.x, 0.0} / std::sqrt(len2) : Vec3{1.0, 0.0, 0.0};
  const Vec3 t2 = glm::cross(v, t1);
  // Section 4.2: a uniform point of the unit disk, its t2 coordinate squeezed so that the point
  // falls on the projection of the visible half-sphere (a half-disk plus half an ellipse).
  const double r = std::sqrt(u1), phi = 2.0 * pi * u2;
  const double p1 = r * std::cos(phi), s = 0.5 * (1.0 + v.z);
  const double p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * r * std::sin(phi);
  // Section 4.3: lift it onto the hemisphere about v; section 3.4: stretch the normal back.
  const Vec3 n_h = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * v;
  return glm::normalize(Vec3{a.x * n_h.x, a.y * n_h.y, std::max(0.0, n_h.z)});
}

}  // namespace ggx

namespace {
const char* kG2Names[] = {"height-correlated", "separable"};
/// Visibility layers thicker than this are smooth enough for the initial grid (hints below
/// integrate/'s thin-layer threshold only): only a fixed direction within ~1e-3 of the horizon.
constexpr double kVisibilityLayerCeiling = 1e-3;
}  // namespace

Ggx::Ggx(ggx::Alpha alpha, double f0, ggx::G2Form g2) : alpha_(alpha), f0_(f0), g2_(g2) {}

ParamValues Ggx::parameters() const {
  ParamValues values{{"f0", f0_}, {"g2", static_cast<double>(g2_)}};
  if (alpha_.x == alpha_.y) values["alpha"] = alpha_.x;
  else values.insert({{"alpha_x", alpha_.x}, {"alpha_y", alpha_.y}});
  return values;
}

std::string Ggx::spec() const { return spec_text({"ggx", parameters()}); }

double Ggx::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return 0.0;  // opposite directions on the horizon
  // i·h = |i + j|/2 for unit i, j: one expression for i and j, so f is reciprocal to the bit.
  const double F = hvd::schlick(0.5 * len, f0_);
  const double value = F * ggx::D(sum / len, alpha_) * ggx::visibility(i, j, alpha_, g2_);
  // Only an alpha so small that pi alpha_x alpha_y underflows can make D infinite (at the mirror).
  if (std::isnan(value)) return 0.0;
  return std::min(value, std::numeric_limits<double>::max());
}

std::string Ggx::glsl_single_scattering() const {
  // D(s/|s|) = |s|^4 / (pi ax ay Q^2), Q = (s_x/ax)^2 + (s_y/ay)^2 + s_z^2 (ggx::D of the unit m,
  // multiplied out); i.h = |s|/2; the visibility as ggx::visibility.
  const std::string den =
      g2_ == ggx::G2Form::height_correlated ? "2.0 * (j.z * r_i + i.z * r_j)" : "(i.z + r_i) * (j.z + r_j)";
  return "  float ggx_value = 0.0;\n"
         "  vec3 s = i + j;\n"
         "  float len = length(s);\n"
         "  if (len > 0.0) {\n"
         "    float F = gz_schlick(0.5 * len, " +
         decimal_literal(f0_) +
         ", 1.0);\n"
         "    vec3 m = s / len;\n"
         "    float x = m.x * " +
         decimal_literal(1.0 / alpha_.x) + ", y = m.y * " + decimal_literal(1.0 / alpha_.y) +
         ";\n"
         "    float q = x * x + y * y + m.z * m.z;\n"
         "    float D = m.z > 0.0 ? " +
         decimal_literal(1.0 / (pi * alpha_.x * alpha_.y)) +
         " / (q * q) : 0.0;\n"
         "    vec3 a = vec3(" +
         decimal_literal(alpha_.x) + ", " + decimal_literal(alpha_.y) +
         ", 1.0);\n"
         "    float r_i = length(a * i), r_j = length(a * j);\n"
         "    float den = " +
         den +
         ";\n"
         "    ggx_value = den > 0.0 ? F * D / den : 0.0;\n"
         "    if (isnan(ggx_value)) ggx_value = 0.0;\n"
         "    ggx_value = min(ggx_value, 3.40282347e38);\n"
         "  }\n";
}

std::optional<GlslF> Ggx::glsl_f() const {
  return GlslF{std::string(kGlslBelowHorizon) + glsl_single_scattering() + "  return ggx_value;\n", {"gz_schlick"}};
}

MassHints Ggx::mass_hints(const Vec3& fixed, Varying) const {
  // D ~ (1 + tan²δ/α²)^-2 about the mirror direction (ψ ≈ 2δ) is half its peak at ψ ≈ 1.3 α:
  // width √2 α, as cook-torrance's √2 m. Towards grazing the lobe hugs the horizon: a layer.
  // Measured on 102 cases of a, g (α = 0.001 … 0.5, anisotropic, separable; θ up to 89.9°) at
  // 1e-9: a second width across the plane of incidence (the lobe is a thin arc there, as the
  // HVD lobes) cost 43% more evaluations and was no more honest; without the layer, 1% more
  // evaluations and the worst true error reached 0.91 of the estimate (0.32 with it).
  const double w = std::sqrt(2.0) * std::min(alpha_.x, alpha_.y);
  // Near grazing the lobe is a thin arc, which no node of the starting grid sees
  // (tests/extremes_test.cpp, GgxThinArcAtAGrazingViewIsHonest).
  HintBuilder hints;
  hints.halfway_lobe(fixed, w);
  // The height-correlated visibility 1/(2 ((j·n) r_k + (k·n) r_j)) (ggx::visibility) holds, for a
  // fixed direction just above the horizon, a layer in k·n as thin as fixed·n: times (k·n) it is
  // (k·n)/(2 (j·n) r_k + 2 (k·n) r_j), flat above k·n ~ (j·n) r_k/r_j and falling to 0 below it,
  // with a 1/(k·n) tail that carries ~(j·n) ln(1/(j·n)) of the mass, which no initial node sees
  // unless the layer is declared (tests/extremes_test.cpp, GgxGrazingVisibilityLayerIsHonest).
  if (g2_ == ggx::G2Form::height_correlated && fixed.z > 0.0) {
    const double r_fixed = ggx::projected_root(fixed, alpha_);
    const double layer = fixed.z * std::max(alpha_.x, alpha_.y) / r_fixed;  // r_k of a grazing k <= max alpha
    if (layer < kVisibilityLayerCeiling) hints.layer(layer);
  }
  return hints.build();
}

std::optional<IncidentSample> Ggx::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  if (!(j.z > 0.0)) return std::nullopt;
  const Vec3 m = ggx::sample_visible_normal(j, alpha_, u[0], u[1]);
  return drawn_sample(*this, j, 2.0 * glm::dot(j, m) * m - j);  // the mirror reflection of j about m
}

double Ggx::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return 0.0;
  // D_visible(j, h)/(4 j·h) (Walter eq. 14) = G1(j) D(h)/(4 j·n).
  return ggx::G1(j, alpha_) * ggx::D(sum / len, alpha_) / (4.0 * j.z);
}

// ---------------------------------------------------------------------------------------------
namespace {

const char* kSources =
    "Walter et al. 2007, EGSR, eq. 20, 33, 34; Heitz 2014, JCGT 3(2), eq. 86 and section 6; "
    "Heitz 2018, JCGT 7(4) (visible-normal sampling)";

std::string given(const char* key, const ParamValues& v) { return std::string(key) + "=" + format_number(v.at(key)); }

/// Alpha from exactly one of alpha, roughness (alpha = R²) or alpha_x with alpha_y.
ggx::Alpha alpha_from(const ParamValues& v, double default_alpha) {
  std::vector<std::string> keys;
  for (const char* key : {"alpha", "roughness", "alpha_x", "alpha_y"})
    if (v.count(key)) keys.push_back(given(key, v));
  const bool x = v.count("alpha_x") > 0, y = v.count("alpha_y") > 0;
  if (keys.size() > (x && y ? 2u : 1u)) {
    std::string list;
    for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
    throw InputError("ggx: " + list +
                     " are alternatives; allowed: exactly one of alpha, roughness, alpha_x with alpha_y");
  }
  if (x != y)
    throw InputError("ggx: " + keys.front() + " needs " + (x ? "alpha_y" : "alpha_x") +
                     "; allowed: alpha_x with alpha_y, or alpha, or roughness");
  if (x) return {v.at("alpha_x"), v.at("alpha_y")};
  if (v.count("roughness")) {
    const double R = v.at("roughness"), a = R * R;
    if (!(a > 0.0))
      throw InputError("ggx: " + given("roughness", v) + " gives alpha = R^2 = 0; allowed: roughness with R^2 > 0");
    return {a, a};
  }
  const double a = v.count("alpha") ? v.at("alpha") : default_alpha;
  return {a, a};
}

ParamInfo alpha_param(const char* name, const std::string& meaning, const char* alternative_of = "") {
  return {.name = name,
          .type = ParamType::real,
          .min = 0.0,
          .max = 1.0,
          .default_value = 0.5,
          .meaning = meaning,
          .optional = true,
          .min_exclusive = true,
          .alternative_of = alternative_of};
}

}  // namespace

void register_ggx_models(std::vector<ModelInfo>& c) {
  constexpr double kDefaultAlpha = 0.5;
  c.push_back(
      {"ggx",
       "GGX (Trowbridge-Reitz) microfacets with Smith masking-shadowing, f = F D G2/(4 (i.n)(j.n)), Schlick F",
       kSources,
       {alpha_param("alpha", "GGX roughness alpha (0.5 when neither alpha, roughness nor alpha_x/alpha_y is given)"),
        alpha_param("roughness", "perceptual roughness R, alpha = R^2 (engines' convention); instead of alpha",
                    "alpha"),
        alpha_param("alpha_x", "alpha along the tangent (local x); with alpha_y, instead of alpha", "alpha"),
        alpha_param("alpha_y", "alpha along the bitangent (local y); with alpha_x", "alpha"),
        {"f0", ParamType::real, 0.0, 1.0, 1.0, "Schlick reflectance at normal incidence (1: F = 1)"},
        {.name = "g2",
         .type = ParamType::choice,
         .min = 0.0,
         .max = 1.0,
         .default_value = 0.0,
         .meaning = "Smith masking-shadowing: 1/(1 + L(i) + L(j)) or G1(i) G1(j)",
         .choices = {kG2Names[0], kG2Names[1]}}},
       {true, true, EnergyClass::plausible},
       {"ggx.norm", "ggx.g1", "ggx.furnace.e11"},
       [=](const ParamValues& v) -> ModelPtr {
         return std::make_shared<Ggx>(alpha_from(v, kDefaultAlpha), v.at("f0"),
                                      static_cast<ggx::G2Form>(static_cast<int>(v.at("g2"))));
       }});
  // ggx-ms: the same parameters but isotropic only (its E(mu) table is over mu alone).
  ModelInfo ms = c.back();
  ms.name = "ggx-ms";
  ms.summary =
      "GGX plus Kulla-Conty multiple-scattering compensation, f = f_ggx + F_ms (1 - E(i.n))(1 - E(j.n)) / "
      "(pi (1 - E_avg)); E from ganzfeld's own table (models/ggx_ms.h)";
  ms.source = std::string(kSources) + "; Kulla & Conty 2017, Revisiting Physically Based Shading at Imageworks";
  std::erase_if(ms.parameters, [](const ParamInfo& p) { return p.name == "alpha_x" || p.name == "alpha_y"; });
  ms.closed_forms = {};
  ms.make = [=](const ParamValues& v) -> ModelPtr {
    return std::make_shared<GgxMs>(alpha_from(v, kDefaultAlpha).x, v.at("f0"),
                                   static_cast<ggx::G2Form>(static_cast<int>(v.at("g2"))));
  };
  c.push_back(ms);
}

}  // namespace ganzfeld
