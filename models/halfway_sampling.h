// The incident-direction draw, and its density, that Ashikhmin–Shirley (models/ashikhmin_shirley.h)
// and Schlick 1994 (models/schlick.h) share: a mixture of a cosine-weighted draw and the reflection
// of j about a halfway vector drawn by the model's own formulas.
#pragma once

#include <array>
#include <numbers>
#include <optional>

#include "models/model.h"

namespace ganzfeld {

/// With probability p_cosine (u[0] < p_cosine) a cosine-weighted draw from (u[1], u[2]), else j
/// reflected about h = halfway(u[1], u[2]). The draw fails where j·n <= 0, j·h <= 0, the result
/// lies on or below the horizon, or model.pdf_incident (the mixture's density, which the model
/// states) is 0 there; otherwise it carries that density.
template <class Halfway>
std::optional<IncidentSample> sample_cosine_or_halfway(const Model& model, const Vec3& j,
                                                       const std::array<double, 3>& u, double p_cosine,
                                                       const Halfway& halfway) {
  if (!(j.z > 0.0)) return std::nullopt;
  Vec3 i;
  if (u[0] < p_cosine) {
    i = sample_cosine(u[1], u[2]);
  } else {
    const Vec3 h = halfway(u[1], u[2]);
    const double jh = glm::dot(j, h);
    if (!(jh > 0.0)) return std::nullopt;
    i = 2.0 * jh * h - j;
  }
  if (!(i.z > 0.0)) return std::nullopt;
  i = glm::normalize(i);
  const double pdf = model.pdf_incident(j, i);
  if (!(pdf > 0.0)) return std::nullopt;
  return IncidentSample{i, pdf};
}

/// The density per steradian of that draw at i: p_cosine (i·n)/pi + (1 - p_cosine) p_h(h)/(4 j·h)
/// with h = (i + j)/|i + j|, j·h = |i + j|/2, and p_h the density of the model's halfway draw;
/// 0 where i·n <= 0 or j·n <= 0.
template <class HalfwayPdf>
double pdf_cosine_or_halfway(const Vec3& j, const Vec3& i, double p_cosine, const HalfwayPdf& halfway_pdf) {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  const double lobe = p_cosine < 1.0 && len > 0.0 ? halfway_pdf(sum / len) / (2.0 * len) : 0.0;
  return p_cosine * i.z / std::numbers::pi + (1.0 - p_cosine) * lobe;
}

}  // namespace ganzfeld
