// Schlick's 1994 BRDF (models/schlick.h) and its registration.
//
// schlick parameters:
//   c  real [0,1]  0.5  reflection factor C at normal incidence (S(1) = C)
//   r  real (0,1]  0.1  roughness: 0 a mirror (refused: a delta), 1 facets of every slope alike
//   p  real (0,1]  1    isotropy: 1 isotropic, towards 0 the facets turn across the scratches (x)
#include "models/schlick.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <boost/math/special_functions/ellint_1.hpp>

#include "models/classic_models.h"
#include "models/halfway_sampling.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace schlick {

double fresnel(double u, double C) noexcept {
  const double x = 1.0 - std::clamp(u, 0.0, 1.0);
  return C + (1.0 - C) * (x * x) * (x * x) * x;
}

double smith(double v, double r) noexcept { return v > 0.0 ? v / (r - r * v + v) : 0.0; }

double zenith(double t, double r) noexcept {
  const double d = 1.0 + (r - 1.0) * t * t;
  return r / (d * d);
}

double azimuth(double w, double p) noexcept { return std::sqrt(p / (p * p - p * p * w * w + w * w)); }

double azimuth_mean(double p) noexcept {
  if (p >= 1.0) return 1.0;
  return 2.0 / pi * std::sqrt(p) * boost::math::ellint_1(std::sqrt((1.0 - p) * (1.0 + p)));
}

double rational_phong(double t, double n) noexcept { return t > 0.0 ? std::min(t, 1.0) / (n - n * t + t) : 0.0; }

}  // namespace schlick

namespace {

/// w = cos of the azimuth of the unit h from the tangent x; 1 at h = n, where the azimuth is
/// undefined and A has no limit (a single direction: any value will do).
double cos_azimuth(const Vec3& h) noexcept {
  const double s = std::hypot(h.x, h.y);
  return s > 0.0 ? h.x / s : 1.0;
}

}  // namespace

Schlick::Schlick(double C, double r, double p) : C_(C), r_(r), p_(p), a_mean_(schlick::azimuth_mean(p)) {}

std::string Schlick::spec() const { return spec_text({"schlick", {{"c", C_}, {"r", r_}, {"p", p_}}}); }

double Schlick::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return 0.0;  // opposite directions on the horizon: no halfway vector
  const Vec3 h = sum / len;
  const double v = std::min(i.z, 1.0), v2 = std::min(j.z, 1.0);
  const double S = schlick::fresnel(0.5 * len, C_);
  // G(v) G(v') Z A/(4 pi v v') = Z A/(4 pi (r - r v + v)(r - r v' + v')): the cosines cancel.
  const double a = p_ == 1.0 ? 1.0 : schlick::azimuth(cos_azimuth(h), p_) / a_mean_;
  // Products of two factors only (commutative in floating point): f is reciprocal to the bit.
  const double single = schlick::zenith(h.z, r_) * a / (4.0 * pi * ((r_ - r_ * v + v) * (r_ - r_ * v2 + v2)));
  const double shadowed = 1.0 - schlick::smith(v, r_) * schlick::smith(v2, r_);
  const double multiple = shadowed / (4.0 * pi * (std::max(v, kGrazingCosFloor) * std::max(v2, kGrazingCosFloor)));
  const double value = S * (single + multiple);
  return std::isfinite(value) ? value : 0.0;
}

std::optional<GlslF> Schlick::glsl_f() const {
  // As f, from s = i + j without cancellation: 1 - u = |i - j|^2 / (4 (1 + u)) (unit i, j);
  // Z = r |s|^4 / (|s_xy|^2 + r s_z^2)^2 (1 - t^2 = |s_xy|^2 / |s|^2); A^2 = p |s_xy|^2 / (p^2 s_y^2 + s_x^2)
  // (p at h = n, where cos_azimuth's w = 1); 1 - G(v) = r (1 - v) / (r - r v + v), so that
  // 1 - G(v) G(v') = (1 - G(v)) + G(v) (1 - G(v')) keeps its digits where both G are near 1.
  const std::string r = decimal_literal(r_), p = decimal_literal(p_), four_pi = decimal_literal(4.0 * pi);
  const std::string floor = decimal_literal(kGrazingCosFloor);
  const std::string azimuth = p_ == 1.0
                                  ? "  float a = 1.0;\n"
                                  : "  float sxy = dot(s.xy, s.xy);\n"
                                    "  float a = " +
                                        decimal_literal(1.0 / a_mean_) + " * (sxy > 0.0 ? sqrt(" + p + " * sxy / (" +
                                        p + " * " + p + " * s.y * s.y + s.x * s.x)) : sqrt(" + p + "));\n";
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  vec3 s = i + j, e = i - j;\n"
                   "  float len = length(s);\n"
                   "  if (!(len > 0.0)) return 0.0;\n"
                   "  float v = min(i.z, 1.0), w = min(j.z, 1.0);\n"
                   "  float u = 0.5 * len, x = clamp(dot(e, e) / (4.0 * (1.0 + u)), 0.0, 1.0), x2 = x * x;\n"
                   "  float S = " +
                   decimal_literal(C_) + " + " + decimal_literal(1.0 - C_) +
                   " * (x2 * x2 * x);\n"
                   "  float q = dot(s.xy, s.xy) + " +
                   r +
                   " * s.z * s.z;\n"
                   "  float Z = " +
                   r + " * ((len * len) / q) * ((len * len) / q);\n" + azimuth + "  float Di = " + r + " - " + r +
                   " * v + v, Dj = " + r + " - " + r +
                   " * w + w;\n"
                   "  float single = Z * a / (" +
                   four_pi +
                   " * (Di * Dj));\n"
                   "  float Gi = v > 0.0 ? v / Di : 0.0, Gj = w > 0.0 ? w / Dj : 0.0;\n"
                   "  float Oi = v > 0.0 ? " +
                   r +
                   " * (1.0 - v) / Di : 1.0;\n"
                   "  float Oj = w > 0.0 ? " +
                   r +
                   " * (1.0 - w) / Dj : 1.0;\n"
                   "  float multiple = (Oi + Gi * Oj) / (" +
                   four_pi + " * (max(v, " + floor + ") * max(w, " + floor +
                   ")));\n"
                   "  float value = S * (single + multiple);\n"
                   "  return isinf(value) || isnan(value) ? 0.0 : value;\n",
               {}};
}

double Schlick::probability_cosine(double mu_j) const noexcept {
  return std::clamp(1.0 - schlick::smith(mu_j, r_), 0.05, 0.95);
}

double Schlick::halfway_pdf(const Vec3& h) const noexcept {
  if (!(h.z > 0.0)) return 0.0;
  const double t = std::min(h.z, 1.0);
  double azimuth_density = 1.0 / (2.0 * pi);
  if (p_ < 1.0) {
    // x = phi'/(pi/2), phi' in [0, pi/2] the azimuth of h from the bitangent folded into one
    // quadrant. The draw x = p b/sqrt(1 - b^2 + p^2 b^2) (b uniform) inverts to
    // b = x/sqrt(p^2 + x^2 (1 - p^2)), db/dx = p^2/(p^2 + x^2 (1 - p^2))^(3/2); a quarter of the
    // draws fall in each quadrant, so the density per radian is (1/4)(2/pi) db/dx.
    const double x = (h.x == 0.0 && h.y == 0.0) ? 0.0 : std::atan2(std::abs(h.x), std::abs(h.y)) / (0.5 * pi);
    const double q = p_ * p_ + x * x * (1.0 - p_ * p_);
    azimuth_density = p_ * p_ / (2.0 * pi * q * std::sqrt(q));
  }
  // cos^2 theta = s drawn with density Z(t) on [0, 1]; d omega = ds d phi/(2 t).
  return 2.0 * t * schlick::zenith(t, r_) * azimuth_density;
}

Vec3 Schlick::sample_halfway(double xi_1, double xi_2) const noexcept {
  const double s = xi_1 / (r_ - r_ * xi_1 + xi_1);  // cos^2 theta
  const double cos_theta = std::sqrt(std::clamp(s, 0.0, 1.0));
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - s));
  double phi = 2.0 * pi * xi_2;
  if (p_ < 1.0) {
    const double q = std::clamp(4.0 * xi_2, 0.0, std::nextafter(4.0, 0.0));
    const int quadrant = static_cast<int>(q);
    const double b = q - quadrant;
    // Schlick's azimuth: phi' = (pi/2) sqrt(p^2 b^2/(1 - b^2 + p^2 b^2)) from the bitangent (y).
    const double phi_prime = 0.5 * pi * std::sqrt(p_ * p_ * b * b / (1.0 - b * b + p_ * p_ * b * b));
    const double from_x = 0.5 * pi - phi_prime;  // first quadrant, measured from the tangent
    phi = quadrant == 0 ? from_x : quadrant == 1 ? pi - from_x : quadrant == 2 ? pi + from_x : 2.0 * pi - from_x;
  }
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

std::optional<IncidentSample> Schlick::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  return sample_cosine_or_halfway(*this, j, u, probability_cosine(j.z),
                                  [this](double xi_1, double xi_2) { return sample_halfway(xi_1, xi_2); });
}

double Schlick::pdf_incident(const Vec3& j, const Vec3& i) const {
  return pdf_cosine_or_halfway(j, i, probability_cosine(j.z), [this](const Vec3& h) { return halfway_pdf(h); });
}

MassHints Schlick::mass_hints(const Vec3& fixed, Varying) const {
  // The second term's floored 1/(k·n) makes (k·n) f ramp to 0 across k·n < kGrazingCosFloor over
  // either direction, whatever `fixed` (h at j = n: 12x dishonest without it): kGrazingLayer.
  return HintBuilder().lobe(mirror(fixed), std::sqrt(2.0 * r_) * p_).layer(kGrazingLayer).build();
}

// ---------------------------------------------------------------------------------------------
void register_schlick_models(std::vector<ModelInfo>& c) {
  c.push_back(
      {"schlick",
       "Schlick's inexpensive BRDF, single material: f = S(u) [G(v) G(v') Z(t) A(w) + 1 - G(v) G(v')]/(4 pi v v'), "
       "S = c + (1 - c)(1 - u)^5, G(v) = v/(r - r v + v), Z = r/(1 + r t^2 - t^2)^2, A = sqrt(p/(p^2 - p^2 w^2 + w^2)) "
       "normalized to mean 1, w the azimuth of h from the tangent (x)",
       "Schlick 1994, An Inexpensive BRDF Model for Physically-based Rendering, Computer Graphics Forum 13(3) "
       "(Eurographics '94), section 5; Walker 1999, MSc thesis (U. Oregon), ch. III Phong [22]",
       {{"c", ParamType::real, 0.0, 1.0, 0.5, "reflection factor at normal incidence, S(1) = c"},
        {.name = "r",
         .type = ParamType::real,
         .min = 0.0,
         .max = 1.0,
         .default_value = 0.1,
         .meaning = "roughness (0 a mirror, refused; 1 facets of every slope alike)",
         .min_exclusive = true},
        {.name = "p",
         .type = ParamType::real,
         .min = 0.0,
         .max = 1.0,
         .default_value = 1.0,
         .meaning = "isotropy (1 isotropic; towards 0 the facets turn across the scratches along x)",
         .min_exclusive = true}},
       {false, true, EnergyClass::not_plausible},
       {"schlick.z.norm", "schlick.a.norm"},
       [](const ParamValues& p) -> ModelPtr { return std::make_shared<Schlick>(p.at("c"), p.at("r"), p.at("p")); }});
}

}  // namespace ganzfeld
