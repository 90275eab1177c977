// The plausibility report (K&P, "General Properties of BRDFs": a physically plausible BRDF is
// non-negative, reciprocal and conserves energy). For every model of the catalogue and a few
// parameter sets, measured — not taken from the model's declared traits:
//   min f                  over a grid of directions (grazing included): non-negativity
//   reciprocity violation  max |f(i,j) − f(j,i)| / max(f(i,j), f(j,i)) over the same grid
//   max albedo             max over incidence of a(i) = ∫ (k·n) f(i,k) dk, by the cubature
//   Ganzfeld               the range of h(j) = ∫ (k·n) f(k,j) dk over viewing directions: the
//                          sphere is invisible in a Ganzfeld (K&P) iff h ≡ 1
// and whether that agrees with the traits the model declares.
#pragma once

#include <string>
#include <vector>

#include "integrate/cubature.h"
#include "models/model.h"

namespace ganzfeld {

struct PlausibilityRow {
  std::string spec;
  std::string note;  ///< why this parameter set is in the report
  Traits declared;
  double min_f = 0.0;
  std::string min_f_at;  ///< "theta_i, theta_j, phi" in degrees
  double reciprocity_violation = 0.0;
  std::string reciprocity_at;
  double max_albedo = 0.0, max_albedo_error = 0.0, max_albedo_theta_i = 0.0;
  double h_min = 0.0, h_max = 0.0, h_error = 0.0;
  bool converged = true;
  long long evaluations = 0;
  // Verdicts from the measurements.
  bool non_negative() const { return min_f >= 0.0; }
  bool reciprocal() const { return reciprocity_violation <= 1e-9; }
  bool conserves() const { return max_albedo <= 1.0 + max_albedo_error + 1e-9; }
  bool ganzfeld_invisible() const { return h_min >= 1.0 - 1e-6 && h_max <= 1.0 + 1e-6; }
  /// The declared traits agree with the measurements (reciprocal flag; "plausible" or
  /// "conserving" requires non-negative, reciprocal and albedo <= 1 at the sampled incidences).
  bool traits_consistent() const;
};

/// The specs the report covers: every analytic model of the catalogue at its defaults plus the
/// parameter sets listed in plausibility.cpp (edge cases, white versions), and the reference
/// forms of the K&P reciprocity claim about Phong and Blinn-Phong.
struct PlausibilityCase {
  std::string spec, note;
};
std::vector<PlausibilityCase> plausibility_cases();

/// Measures one model (the albedo and h integrals to `tolerance`).
PlausibilityRow measure_plausibility(const Model& model, const std::string& note, double tolerance);

/// Every case, in parallel (deterministic output order).
std::vector<PlausibilityRow> plausibility_report(double tolerance);

/// docs/plausibility.md: the table, the verdicts and the answer to K&P's claim.
std::string plausibility_markdown(const std::vector<PlausibilityRow>& rows, double tolerance,
                                  const std::string& command);

}  // namespace ganzfeld
