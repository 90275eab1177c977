// The incident-direction draw that Ashikhmin–Shirley (models/ashikhmin_shirley.h) and Schlick 1994
// (models/schlick.h) share: a mixture of a cosine-weighted draw and the reflection of j about a
// halfway vector drawn by the model's own formulas.
#pragma once

#include <array>
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

}  // namespace ganzfeld
