// `ganzfeld verify`: every closed form printed in Koenderink & Pont against our cubature on a grid
// that includes the extremes (sky pole at the nadir and 0.999 from it, grazing views at 0 and
// 1e-6, normal incidence). A printed form that disagrees by more than kAgreement is an erratum;
// we then derive, implement and check a corrected form. The report becomes docs/errata.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ganzfeld {

/// A printed form "matches" when it agrees with cubature to this.
inline constexpr double kAgreement = 1e-9;
/// Cubature tolerance for the references: two orders below kAgreement so that a disagreement
/// is the formula's, not the integrator's.
inline constexpr double kReferenceTolerance = 1e-11;
/// A reference that stops short of kReferenceTolerance (its budget spent) still classifies a form
/// while its stated error is below this: a disagreement beyond kAgreement cannot then be its own.
inline constexpr double kReferenceResolution = kAgreement / 10;

struct CheckResult {
  std::string id;
  std::string source;       ///< where in the paper the claim is printed
  std::string models;       ///< the model specs the claim was checked on
  std::string printed;      ///< the claim as printed
  std::string corrected;    ///< our corrected form (empty when the printed one matches)
  std::string explanation;  ///< why it fails and how the correction was derived
  bool erratum = false;
  double max_abs_error = 0.0;
  std::optional<double> corrected_max_abs_error;
  long points = 0;
  double max_reference_error = 0.0;  ///< largest error estimate of the cubature references
  bool references_converged = true;
};

std::vector<CheckResult> run_verification();

/// Checks of the halfway-vector-disk models (Edwards et al.; reports/verify_hvd.cpp), appended
/// to run_verification() after the Koenderink–Pont checks.
std::vector<CheckResult> hvd_checks();
/// Checks of the microfacet models (GGX, Charlie sheen; reports/verify_ggx.cpp), appended after
/// the halfway-vector-disk checks.
std::vector<CheckResult> ggx_checks();
/// Checks of the other catalogue models' printed forms (Ashikhmin–Shirley, Schlick, Kajiya & Kay;
/// reports/verify_catalogue.cpp), appended after the microfacet checks.
std::vector<CheckResult> catalogue_checks();

/// True when every matching or corrected form agrees to kAgreement and all references converged.
bool verification_passed(const std::vector<CheckResult>& checks);

/// `verify --json` (and the Python module's ganzfeld.verify()): {checks: [{id, source, status
/// ("matches" or "erratum"), max_abs_error, corrected_max_abs_error (null when none), points,
/// models, printed, [corrected], max_reference_error, references_converged}], agreement, passed}.
nlohmann::ordered_json verify_json(const std::vector<CheckResult>& checks);

/// docs/errata.md, stamped with the command that generates it.
std::string errata_markdown(const std::vector<CheckResult>& checks, const std::string& command);

}  // namespace ganzfeld
