// The extremes grid: every registered model (and mixtures) with its
// parameters at the ends of their documented ranges, the laws f, g, h, a at extreme directions
// (i·n ∈ {−1, −0.999, 0, 1e-9, 1e-6, 1}, j·n ∈ {0, 1e-9, 1e-6, 1}, φ ∈ {0, π/2, π}), the engine
// at a fixed absolute tolerance judged against the independent reference (reference/, Boost
// quadrature written apart from integrate/). Each result is finite or not; converged or not; and
// when converged, honest (|engine − reference| ≤ engine estimate + reference error) or dishonest.
// The references are tried in order, gauss_kronrod<61>, gauss_kronrod<31> with the nesting
// swapped, Boost's tanh_sinh (reference/), and the first resolved one judges; a fourth, tanh_sinh
// about the antipode of the fixed direction, is a witness: asked where the engine disagrees with
// the judge, and one of the unresolved bounds where none of the three is resolved, never alone. Where the engine
// disagrees with it, another resolved one that agrees with the engine makes the case count as
// "references disagree", listed, not dropped.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "integrate/laws.h"
#include "reference/lune_reference.h"

namespace ganzfeld {

struct ExtremesCase;

struct ExtremesOptions {
  double engine_tolerance = 1e-8;  ///< the engine's absolute tolerance on every integral
  /// Only these catalogue model names ("mixture" for the mixtures); empty: every model.
  std::vector<std::string> models;
  /// The slice ctest runs: the default spec of each model and the grid's corners only.
  bool quick = false;
  /// The whole direction grid, but each model at its defaults (and the extra specs) only: the
  /// parameters' ends multiply the run time by about ten.
  bool defaults_only = false;
  /// Called after each case (serialized, in completion order) with the cases done and the total:
  /// a grid at the parameters' ends runs for hours, and a dishonest case should not wait for it.
  std::function<void(const ExtremesCase&, std::size_t done, std::size_t total)> on_case;
};

/// One spec of the grid and why it is there ("default", "alpha=min", ...).
struct ExtremesSpec {
  std::string model, spec, why;
};

/// The specs of the grid: each model's defaults, each parameter at either end of its range (an
/// exponent's end is capped at kExtremesExponentCap), and the extra cases listed in extremes.cpp
/// (anisotropic radii, mixtures). Measured models need a data file and are skipped here.
std::vector<ExtremesSpec> extremes_specs(const ExtremesOptions& options);
/// α ∈ {min, 1000}: beyond 1000 a lobe is narrower than the reference resolves.
inline constexpr double kExtremesExponentCap = 1000.0;
/// Evaluations of f the reference may spend on one case (about a second) before the case is
/// reported as unresolved.
inline constexpr long long kExtremesReferenceBudget = 5'000'000;
/// The tanh_sinh reference's budget where the first is unresolved: its nested levels cost more
/// per case (a few hundred nodes per panel and level), and it runs on a few percent of the cases.
inline constexpr long long kExtremesTanhSinhBudget = 20'000'000;
/// The antipode reference's budget (reference::Options::about_antipode; a witness where the engine
/// disagrees with the judging reference).
inline constexpr long long kExtremesAntipodeBudget = 10'000'000;

struct ExtremesCase {
  std::string spec;
  Law law = Law::f;
  Vec3 i{0, 0, 1}, j{0, 0, 1};
  std::string where;  ///< "i·n=..., j·n=..., phi=..."
  Estimate engine;
  double reference = 0.0, reference_error = 0.0;
  /// Which reference judged: "gauss_kronrod<61>", "gauss_kronrod<31>, swapped" or "tanh_sinh" (or,
  /// where none is resolved and its bound is the closest that excludes the engine, "tanh_sinh, about
  /// the antipode").
  std::string reference_rule;
  double second_reference = 0.0,
         second_reference_error = 0.0;  ///< another reference, where the engine disagrees with the first
  bool finite = true, converged = true, dishonest = false, references_disagree = false;
  /// The reference ran out of its budget or its error exceeds the engine's tolerance (times |value|
  /// where that exceeds 1): this case is not judged (counted and listed, not dropped).
  bool reference_unresolved = false;
  double seconds = 0.0;  ///< wall time of the case (engine and references)
};

struct ExtremesRow {
  std::string model;
  int specs = 0;
  std::vector<std::string> refused;  ///< specs the parser refused (e.g. kd + ks > 1), with its message
  int cases = 0, non_finite = 0, not_converged = 0, dishonest = 0, references_disagree = 0, unresolved = 0;
  int judged_by_fallback = 0;         ///< judged cases whose first reference was unresolved
  double seconds = 0.0;               ///< wall time of the model's cases
  std::vector<ExtremesCase> flagged;  ///< every non-finite, not converged, dishonest or doubtful case
  std::vector<ExtremesCase> all;      ///< every case (for the CSV)
};

/// Runs the grid (cases in parallel; rows in catalogue order).
std::vector<ExtremesRow> extremes_report(const ExtremesOptions& options);

/// The model names of the grid in catalogue order ("mixture" for the mixtures), as its rows are.
std::vector<std::string> extremes_models(const ExtremesOptions& options);

/// One case as JSON: its spec, law, directions, the engine's estimate, the references and the
/// verdict's flags (extremes --json's flagged cases and the kept rows).
nlohmann::ordered_json extremes_case_json(const ExtremesCase& c);
/// One model's row with every case, as JSON (with the options it was measured with and its wall
/// time), and back: a grid that runs for hours is resumed model by model (extremes --keep DIR).
std::string extremes_row_json(const ExtremesRow& row, const ExtremesOptions& options, double wall_seconds);
struct KeptExtremesRow {
  ExtremesRow row;
  double wall_seconds = 0.0;
};
/// Reads extremes_row_json's text (counts and flagged cases recomputed from the cases); throws
/// InputError naming `path` when it is not one, or when it was measured with other options
/// (tolerance, quick, defaults only).
KeptExtremesRow extremes_row_from_json(const std::string& text, const ExtremesOptions& options,
                                       const std::string& path);

/// The references judge_case asks, in order: gauss_kronrod<61>, gauss_kronrod<31> swapped and
/// tanh_sinh, the judges (the first resolved one judges), and tanh_sinh about the antipode, a witness.
inline constexpr std::size_t kExtremesReferences = 4, kExtremesJudges = 3;
/// judge_case's verdict on c.engine (finite, converged): sets c's reference, its rule's name and the
/// flags dishonest, references_disagree and reference_unresolved from `reference(k)`, the k-th
/// reference in that order, asked only when the rule needs it. Exposed for the tests, which give it
/// made-up values.
void judge_against_references(ExtremesCase& c, const std::function<const reference::Value&(std::size_t)>& reference,
                              double engine_tolerance);

/// Judges one case: engine at the tolerance against the reference (and the second reference when
/// they disagree). Exposed for the tests, which may give the engine a smaller evaluation budget
/// (a case that does not converge within it is not judged).
ExtremesCase judge_case(const Model& model, Law law, const Vec3& i, const Vec3& j, double engine_tolerance,
                        long long engine_budget = CubatureOptions{}.max_evaluations);

/// docs/reliability-extremes.md: the method, the per-model table, the targets met or
/// missed, every dishonest case and where the references disagree, and the worst of the other
/// flagged cases (all of them are in the CSV named `csv_file`, when given); `command` is the
/// stamp, `seconds` the run's wall time (`resumed`: summed over the runs that measured its rows).
std::string extremes_markdown(const std::vector<ExtremesRow>& rows, const ExtremesOptions& options,
                              const std::string& command, double seconds, const std::string& csv_file = "",
                              bool resumed = false);

/// Every case of the grid, one CSV row each (judged or not; `where` gives the cosines and the
/// azimuth the directions are made from, as add_jobs in extremes.cpp makes them), stamped with
/// `command` on its first line.
std::string extremes_csv(const std::vector<ExtremesRow>& rows, const std::string& command);

}  // namespace ganzfeld
