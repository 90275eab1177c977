// Ashikhmin & Shirley's anisotropic Phong BRDF (models/ashikhmin_shirley.h) and its registration.
//
// ashikhmin-shirley parameters:
//   rd  real [0,1]      0.5  diffuse reflectance R_d (the substrate under the specular coat)
//   rs  real [0,1]      0.05 specular reflectance at normal incidence R_s (Schlick's F(1))
//   nu  real [0,10000]  100  Phong-like exponent along the tangent (local x)
//   nv  real [0,10000]  100  Phong-like exponent along the bitangent (local y)
#include "models/ashikhmin_shirley.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/halfway_sampling.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

double pow5(double x) noexcept { return (x * x) * (x * x) * x; }

}  // namespace

AshikhminShirley::AshikhminShirley(double rd, double rs, double nu, double nv)
    : rd_(rd), rs_(rs), nu_(nu), nv_(nv), norm_(std::sqrt((nu + 1.0) * (nv + 1.0))) {}

std::string AshikhminShirley::spec() const {
  return spec_text({"ashikhmin-shirley", {{"rd", rd_}, {"rs", rs_}, {"nu", nu_}, {"nv", nv_}}});
}

double AshikhminShirley::exponent(const Vec3& h) const noexcept {
  // (n_u (h·u)^2 + n_v (h·v)^2)/(1 - (h·n)^2) with 1 - (h·n)^2 = (h·u)^2 + (h·v)^2 (no cancellation
  // near n); at h = n the azimuth is undefined but (h·n)^e = 1 for any e.
  const double xx = h.x * h.x, yy = h.y * h.y, s = xx + yy;
  return s > 0.0 ? (nu_ * xx + nv_ * yy) / s : 0.0;
}

double AshikhminShirley::diffuse(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double mi = std::min(i.z, 1.0), mj = std::min(j.z, 1.0);
  // The two factors multiplied first: a product of two is commutative in floating point, so f is
  // reciprocal to the bit.
  const double both = (1.0 - pow5(1.0 - 0.5 * mi)) * (1.0 - pow5(1.0 - 0.5 * mj));
  return 28.0 * rd_ / (23.0 * pi) * (1.0 - rs_) * both;
}

double AshikhminShirley::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double d = diffuse(i, j);
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  const double mu_max = std::max(i.z, j.z);
  // Opposite directions on the horizon (no halfway vector), or both on the horizon, where the
  // specular term has no limit (a null set): the diffuse part alone.
  if (!(len > 0.0) || !(mu_max > 0.0)) return d;
  const Vec3 h = sum / len;
  const double kh = 0.5 * len;  // k·h for unit i, j: one symmetric expression, so f is reciprocal to the bit
  const double F = rs_ + (1.0 - rs_) * pow5(1.0 - std::min(kh, 1.0));
  const double lobe = h.z > 0.0 ? std::pow(std::min(h.z, 1.0), exponent(h)) : 0.0;
  const double s = norm_ / (8.0 * pi) * lobe / (kh * mu_max) * F;
  return std::isfinite(s) ? d + s : d;
}

std::optional<GlslF> AshikhminShirley::glsl_f() const {
  // As f, from s = i + j without cancellation: 1 - (1 - x)^5 = x (1 + y + y^2 + y^3 + y^4), y = 1 - x;
  // 1 - k.h = |i - j|^2 / (4 (1 + k.h)) (unit i, j); 1 - h.n = |s_xy|^2 / (|s| (|s| + s_z)); e(h) from
  // s_x^2 and s_y^2, which scale as h's.
  const std::string diffuse = decimal_literal(28.0 * rd_ / (23.0 * pi) * (1.0 - rs_));
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float xi = 0.5 * min(i.z, 1.0), xj = 0.5 * min(j.z, 1.0), yi = 1.0 - xi, yj = 1.0 - xj;\n"
                   "  float d = " +
                   diffuse +
                   " * ((xi * (1.0 + yi * (1.0 + yi * (1.0 + yi * (1.0 + yi))))) *\n"
                   "            (xj * (1.0 + yj * (1.0 + yj * (1.0 + yj * (1.0 + yj))))));\n"
                   "  vec3 s = i + j, e = i - j;\n"
                   "  float len = length(s), mu_max = max(i.z, j.z);\n"
                   "  if (!(len > 0.0) || !(mu_max > 0.0)) return d;\n"
                   "  float kh = 0.5 * len, x = clamp(dot(e, e) / (4.0 * (1.0 + kh)), 0.0, 1.0), x2 = x * x;\n"
                   "  float F = " +
                   decimal_literal(rs_) + " + " + decimal_literal(1.0 - rs_) +
                   " * (x2 * x2 * x);\n"
                   "  float sxx = s.x * s.x, syy = s.y * s.y, sxy = sxx + syy;\n"
                   "  float exponent = sxy > 0.0 ? (" +
                   decimal_literal(nu_) + " * sxx + " + decimal_literal(nv_) +
                   " * syy) / sxy : 0.0;\n"
                   "  float lobe = s.z > 0.0 ? gz_pow_pair(s.z / len, sxy / (len * (len + s.z)), exponent) : 0.0;\n"
                   "  float spec = " +
                   decimal_literal(norm_ / (8.0 * pi)) +
                   " * lobe / (kh * mu_max) * F;\n"
                   "  return isinf(spec) || isnan(spec) ? d : d + spec;\n",
               {"gz_pow_pair"}};
}

double AshikhminShirley::halfway_pdf(const Vec3& h) const noexcept {
  if (!(h.z > 0.0)) return 0.0;
  return norm_ / (2.0 * pi) * std::pow(std::min(h.z, 1.0), exponent(h));
}

Vec3 AshikhminShirley::sample_halfway(double xi_1, double xi_2) const noexcept {
  // xi_1 picks a quadrant and a uniform number within it; the azimuth within the first quadrant
  // is mirrored into the others (the density is even in h·u and h·v).
  const double q = std::clamp(4.0 * xi_1, 0.0, std::nextafter(4.0, 0.0));
  const int quadrant = static_cast<int>(q);
  const double xi = q - quadrant;
  const double phi_0 = std::atan(std::sqrt((nu_ + 1.0) / (nv_ + 1.0)) * std::tan(0.5 * pi * xi));
  const double phi = quadrant == 0 ? phi_0 : quadrant == 1 ? pi - phi_0 : quadrant == 2 ? pi + phi_0 : 2.0 * pi - phi_0;
  const double c = std::cos(phi), s = std::sin(phi);
  const double e = nu_ * c * c + nv_ * s * s;
  const double cos_theta = std::pow(1.0 - xi_2, 1.0 / (e + 1.0));
  const double sin_theta = std::sqrt(std::max(0.0, (1.0 - cos_theta) * (1.0 + cos_theta)));
  return {sin_theta * c, sin_theta * s, cos_theta};
}

double AshikhminShirley::probability_diffuse() const noexcept {
  const double w_d = rd_ * (1.0 - rs_), w_s = rs_ + (1.0 - rs_) / 21.0;
  return w_d / (w_d + w_s);
}

std::optional<IncidentSample> AshikhminShirley::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  return sample_cosine_or_halfway(*this, j, u, probability_diffuse(),
                                  [this](double xi_1, double xi_2) { return sample_halfway(xi_1, xi_2); });
}

double AshikhminShirley::pdf_incident(const Vec3& j, const Vec3& i) const {
  return pdf_cosine_or_halfway(j, i, probability_diffuse(), [this](const Vec3& h) { return halfway_pdf(h); });
}

MassHints AshikhminShirley::mass_hints(const Vec3& fixed, Varying) const {
  const double along = 2.0 / std::sqrt(std::max(nu_, nv_) + 1.0);
  return HintBuilder().lobe(mirror(fixed), along, along * std::max(fixed.z, 1e-3)).build();
}

// ---------------------------------------------------------------------------------------------
void register_ashikhmin_shirley_models(std::vector<ModelInfo>& c) {
  const ParamInfo rd{"rd", ParamType::real, 0.0, 1.0, 0.5, "diffuse reflectance R_d of the substrate"};
  const ParamInfo rs{"rs", ParamType::real, 0.0, 1.0, 0.05, "specular reflectance at normal incidence R_s (Schlick F)"};
  c.push_back(
      {"ashikhmin-shirley",
       "anisotropic Phong: f = sqrt((nu+1)(nv+1))/(8 pi) (h.n)^(nu (h.x)^2 + nv (h.y)^2)/(1 - (h.n)^2) F(k.h) / "
       "((k.h) max(i.n, j.n)) + 28 rd/(23 pi) (1 - rs)(1 - (1 - i.n/2)^5)(1 - (1 - j.n/2)^5), F Schlick's with rs",
       "Ashikhmin & Shirley 2000, An Anisotropic Phong BRDF Model, Journal of Graphics Tools 5(2) 25-32",
       {rd,
        rs,
        {"nu", ParamType::real, 0.0, 10000.0, 100.0, "Phong-like exponent along the tangent (local x)"},
        {"nv", ParamType::real, 0.0, 10000.0, 100.0, "Phong-like exponent along the bitangent (local y)"}},
       {false, true, EnergyClass::plausible},
       {"ashikhmin-shirley.pdf", "ashikhmin-shirley.diffuse"},
       [](const ParamValues& p) -> ModelPtr {
         return std::make_shared<AshikhminShirley>(p.at("rd"), p.at("rs"), p.at("nu"), p.at("nv"));
       }});
}

}  // namespace ganzfeld
