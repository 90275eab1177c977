#include "models/mixture.h"

#include <algorithm>
#include <cmath>

#include "models/registry.h"
#include "util/hash.h"

namespace ganzfeld {

Mixture::Mixture(std::vector<Lobe> lobes) : lobes_(std::move(lobes)) { normalize_weights(lobes_); }

std::string Mixture::spec() const {
  Spec spec;
  for (const auto& lobe : lobes_)
    spec.terms.push_back({lobe.weight, parse_spec(lobe.model->spec()).terms.front().model});
  return spec_text(spec);
}

std::string Mixture::content_digest() const {
  std::string joined;  // '+' keeps the lobe boundaries: ("", d) and (d, "") differ
  bool any = false;
  for (const auto& lobe : lobes_) {
    const std::string digest = lobe.model->content_digest();
    any = any || !digest.empty();
    joined += digest + "+";
  }
  return any ? util::content_digest_of(joined) : std::string();
}

Traits Mixture::traits() const {
  Traits t{true, true, EnergyClass::conserving};
  for (const auto& lobe : lobes_) {
    const Traits lt = lobe.model->traits();
    t.isotropic = t.isotropic && lt.isotropic;
    t.reciprocal = t.reciprocal && lt.reciprocal;
    // K&P: a mixture is plausible if its components are; it is conserving only if all are.
    t.energy = std::max(t.energy, lt.energy);
  }
  return t;
}

double Mixture::f(const Vec3& i, const Vec3& j) const noexcept {
  double sum = 0.0;
  for (const auto& lobe : lobes_) sum += lobe.weight * lobe.model->f(i, j);
  return sum;
}

std::optional<IncidentSample> Mixture::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  double below = 0.0;
  for (std::size_t k = 0; k < lobes_.size(); ++k) {
    const double w = lobes_[k].weight;
    if (u[0] < below + w || k + 1 == lobes_.size()) {
      // Rescale u[0] within the chosen lobe's interval so the lobe sees a fresh uniform number.
      const double within = std::clamp((u[0] - below) / w, 0.0, std::nextafter(1.0, 0.0));
      auto s = lobes_[k].model->sample_incident(j, {within, u[1], u[2]});
      if (!s) return std::nullopt;
      s->pdf = pdf_incident(j, s->i);
      if (!(s->pdf > 0.0)) return std::nullopt;
      return s;
    }
    below += w;
  }
  return std::nullopt;
}

double Mixture::pdf_incident(const Vec3& j, const Vec3& i) const {
  double sum = 0.0;
  for (const auto& lobe : lobes_) sum += lobe.weight * lobe.model->pdf_incident(j, i);
  return sum;
}

double Mixture::mirror_reflectance(double cos_theta) const noexcept {
  double sum = 0.0;
  for (const auto& lobe : lobes_) sum += lobe.weight * lobe.model->mirror_reflectance(cos_theta);
  return sum;
}

MassHints Mixture::mass_hints(const Vec3& fixed, Varying varying) const {
  // Every cylinder model puts its cylinders along x, so the lobes' creases share one frame.
  HintBuilder all;
  for (const auto& lobe : lobes_) all.merge(lobe.model->mass_hints(fixed, varying));
  return all.build();
}

}  // namespace ganzfeld
