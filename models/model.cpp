// Defaults of the Model interface (models/model.h).
#include "models/model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ganzfeld {

void Model::f_batch(std::span<const Vec3> i, std::span<const Vec3> j, std::span<double> out) const noexcept {
  for (std::size_t m = 0; m < out.size(); ++m) out[m] = f(i[m], j[m]);
}

MassHints Model::mass_hints(const Vec3&, Varying) const { return {}; }

Vec3 sample_cosine(double u1, double u2) noexcept {
  const double r = std::sqrt(std::clamp(u1, 0.0, 1.0));
  const double phi = 2.0 * std::numbers::pi * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u1))};
}

std::optional<IncidentSample> Model::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  if (!(j.z > 0.0)) return std::nullopt;
  const Vec3 i = sample_cosine(u[1], u[2]);
  if (!(i.z > 0.0)) return std::nullopt;  // u1 = 1 exactly: on the horizon, density 0
  return IncidentSample{i, i.z * std::numbers::inv_pi};
}

std::optional<IncidentSample> drawn_sample(const Model& model, const Vec3& j, const Vec3& i) {
  if (!(i.z > 0.0)) return std::nullopt;
  const double pdf = model.pdf_incident(j, i);
  if (!(pdf > 0.0)) return std::nullopt;
  return IncidentSample{glm::normalize(i), pdf};
}

bool has_mirror_delta(const Model& model) noexcept {
  constexpr int kSteps = 64;
  for (int k = 1; k <= kSteps; ++k)
    if (model.mirror_reflectance(static_cast<double>(k) / kSteps) > 0.0) return true;
  return false;
}

double Model::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  return i.z * std::numbers::inv_pi;
}

}  // namespace ganzfeld
