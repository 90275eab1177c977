// Kajiya's analytic fibre case (models/kajiya.h) and its registration.
//
// kajiya parameters:
//   kd  real [0,1]      0.3  diffuse reflectance of the fibres (kd/pi at normal incidence); kd + ks <= 1
//   ks  real [0,1]      0.7  weight of the highlight cone; kd + ks <= 1
//   n   real [1,10000]  20   exponent of the cosine from the cone
#include "models/kajiya.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/classic_models.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {
/// sin of the angle between the unit v and the fibre axis x, without 1 - x^2 cancellation.
double sin_to_axis(const Vec3& v) noexcept { return std::min(1.0, std::hypot(v.y, v.z)); }
}  // namespace

Kajiya::Kajiya(double kd, double ks, double n) : kd_(kd), ks_(ks), n_(n) {}

std::string Kajiya::spec() const { return spec_text({"kajiya", {{"kd", kd_}, {"ks", ks_}, {"n", n_}}}); }

double Kajiya::cone_cosine(const Vec3& i, const Vec3& j) noexcept {
  return sin_to_axis(i) * sin_to_axis(j) - i.x * j.x;
}

double Kajiya::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double c = cone_cosine(i, j);
  const double highlight = c > 0.0 ? std::pow(std::min(c, 1.0), n_) : 0.0;
  return (kd_ * sin_to_axis(i) / pi + ks_ * highlight) / std::max(i.z, kGrazingCosFloor);
}

std::optional<GlslF> Kajiya::glsl_f() const {
  // As f, with 1 - c from the fibre-plane vectors (i.x, sin(t, i)) and (j.x, -sin(t, j)): for unit i, j,
  // c = -cos(a + b) (a, b their angles to the axis), 1 - c = |(i.x + j.x, sin(t, i) - sin(t, j))|^2 / 2,
  // formed without cancellation at the cone, where the power needs it.
  return GlslF{std::string(kGlslBelowHorizon) +
                   "  float si = min(1.0, length(i.yz)), sj = min(1.0, length(j.yz));\n"
                   "  vec2 d = vec2(i.x + j.x, si - sj);\n"
                   "  float highlight = gz_pow_pair(si * sj - i.x * j.x, 0.5 * dot(d, d), " +
                   decimal_literal(n_) +
                   ");\n"
                   "  return (" +
                   decimal_literal(kd_ / pi) + " * si + " + decimal_literal(ks_) + " * highlight) / max(i.z, " +
                   decimal_literal(kGrazingCosFloor) + ");\n",
               {"gz_pow_pair"}};
}

MassHints Kajiya::mass_hints(const Vec3& fixed, Varying varying) const {
  HintBuilder hints;
  const double width = 1.0 / std::sqrt(n_);
  // The cone k·x = -fixed·x: k = (-fixed_x, s cos beta, s sin beta), s = sin(t, fixed), beta in [0, pi].
  const double s = sin_to_axis(fixed);
  constexpr int kPoints = 7;
  if (ks_ > 0.0 && s > 0.0)
    for (int m = 0; m < kPoints; ++m) {
      const double beta = pi * m / (kPoints - 1);
      hints.lobe(Vec3{-fixed.x, s * std::cos(beta), s * std::sin(beta)}, width);
    }
  if (varying == Varying::incident) hints.layer(kGrazingLayer);
  return hints.build();
}

// ---------------------------------------------------------------------------------------------
void register_kajiya_models(std::vector<ModelInfo>& c) {
  c.push_back(
      {"kajiya",
       "Kajiya's anisotropic reflection, analytic fibre case (smooth cylinders along the tangent x, Kajiya & Kay): "
       "f = [kd sin(t,i)/pi + ks max(0, sin(t,i) sin(t,j) - (t.i)(t.j))^n]/(i.n) (not reciprocal)",
       "Kajiya 1985, Anisotropic Reflection Models, SIGGRAPH '85 (Kirchhoff; tabulated per microgeometry); "
       "Kajiya & Kay 1989, Rendering Fur with Three Dimensional Textures, SIGGRAPH '89, section 3.3 (the "
       "cylinder in closed form); Walker 1999, MSc thesis (U. Oregon), ch. III Kajiya",
       {kd_param(0.3), ks_param(0.7), n_param(20.0, "exponent of the cosine from the cone of mirror directions")},
       {false, false, EnergyClass::not_plausible},
       {"kajiya.cylinder"},
       [](const ParamValues& p) -> ModelPtr {
         require_sum_at_most_one("kajiya", "kd", p.at("kd"), "ks", p.at("ks"));
         return std::make_shared<Kajiya>(p.at("kd"), p.at("ks"), p.at("n"));
       }});
}

}  // namespace ganzfeld
