// Partitive mixture f = sum_k mu_k f_k / sum_k mu_k (K&P, "partitive mixture of BRDFs").
// Every law is linear in f, so a mixture's g, h, a, r are the weighted sums of its lobes'.
#pragma once

#include <vector>

#include "models/spec.h"

namespace ganzfeld {

class Mixture final : public Model {
 public:
  /// Weights must be positive; they are normalized here.
  explicit Mixture(std::vector<Lobe> lobes);
  std::string spec() const override;
  /// One digest of the lobes' digests in spec order; "" when no lobe has a data file.
  std::string content_digest() const override;
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// Picks a lobe with probability equal to its weight (u[0]), then samples that lobe;
  /// the density is the weighted sum of the lobes' densities.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;
  /// The weighted sum of the lobes' mirror reflectances.
  double mirror_reflectance(double cos_theta) const noexcept override;
  const std::vector<Lobe>& lobes() const { return lobes_; }

 private:
  std::vector<Lobe> lobes_;
};

}  // namespace ganzfeld
