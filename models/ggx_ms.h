// ggx-ms: GGX plus Kulla–Conty multiple-scattering compensation (Kulla & Conty 2017,
// "Revisiting Physically Based Shading at Imageworks", SIGGRAPH course, "Energy compensation"):
//
//   f = f_ggx + F_ms f_ms,   f_ms(i, j) = (1 − E(μ_i))(1 − E(μ_j)) / (π (1 − E_avg)),
//   F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg)),  F_avg = 2 ∫ F(μ) μ dμ = f0 + (1 − f0)/21
//
// (Schlick's F; F_ms = 1 for f0 = 1). E(μ) = ∫ f₁ cos is GGX's albedo with F = 1 and
// E_avg = 2 ∫ E(μ) μ dμ. With f0 = 1, ∫ f_ms cos θ_j dω_j = 1 − E(μ_i), so the albedo is exactly
// 1 (the white furnace) when E is exact and E_avg is the average of the E used.
//
// E is ganzfeld's own: a table in μ built at construction (cached per alpha and g2) from
// ggx::ggx_albedo_rule (models/ggx_energy.h, tensor Gauss–Legendre over the half vector; the
// cubature lives in integrate/, which models/ cannot call), cubic in μ^(1/4) on nodes doubled
// until the interpolant matches the rule at the new nodes within kEnergyTableTolerance; E_avg
// is the exact μ-weighted integral of that interpolant, so the compensation adds exactly
// 1 − E_table(μ) and the white-furnace error is |E(μ) − E_table(μ)| (EnergyTable::error).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "models/ggx.h"

namespace ganzfeld {

namespace ggx {

/// The nodes are doubled until the interpolant deviates from the rule by at most this at every
/// new node (the midpoints of the coarser table).
inline constexpr double kEnergyTableTolerance = 1e-6;

/// E on nodes uniform in t = μ^(1/4), Catmull–Rom between them (cubic, C1; quadratic
/// extrapolation beyond the ends). Dense at grazing, where E changes fastest and is not smooth:
/// E ≈ 1 − c μ ln(1/μ) (height-correlated Smith, E(0) = 1), which is smooth enough in t.
struct EnergyTable {
  std::vector<double> E;  ///< E at μ = (k/n)⁴, k = 0 … n
  double E_avg = 1.0;     ///< 2 ∫ E_table(μ) μ dμ, exact for the interpolant
  /// |E − E_table| measured at the last doubling's new nodes (those of the coarser table, an
  /// upper estimate for the kept finer one) plus the rule's own error estimate: measured, not
  /// a proof.
  double error = 0.0;
  double at(double mu) const noexcept;  ///< E_table(μ), μ clamped to [0, 1]
};

/// The table for (alpha, g2), built once per pair and cached (thread-safe).
std::shared_ptr<const EnergyTable> energy_table(double alpha, G2Form g2);

}  // namespace ggx

class GgxMs final : public Model {
 public:
  GgxMs(double alpha, double f0, ggx::G2Form g2);
  std::string spec() const override;
  Traits traits() const override { return {true, true, EnergyClass::plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override { return ggx_.mass_hints(fixed, varying); }
  /// With probability E(μ_j) a visible-normal draw of the GGX lobe (u[0], u[1]), else a cosine
  /// draw for the compensation; u[2] chooses. pdf: the same mixture of the two densities.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;
  const ggx::EnergyTable& energy() const { return *energy_; }

 private:
  Ggx ggx_;
  std::shared_ptr<const ggx::EnergyTable> energy_;
  double f_ms_scale_;  ///< F_ms / (π (1 − E_avg)), 0 when E_avg = 1
};

}  // namespace ganzfeld
