// The parameters a fit varies, their bounds and the spec they make.
//
// A model's free parameters are the real-valued items of its canonical spec (Model::spec(): the
// parametrization the model is in, e.g. ggx's alpha rather than roughness, hvd-empirical's f0
// rather than eta, rs rather than rsu/rsv), minus those --fixed names. Integer and choice
// parameters are never varied (ggx's g2, hapke's phase, perfect-backscatter's integer alpha); a
// model left with no real parameter cannot be fitted. Bounds are the registry's ranges
// (models/registry.h), closed: a range open at 0 starts at kOpenFloor × its width.
//
// The optimizer works on u ∈ [0, 1] per parameter:
//   linear  x = lo + u (hi − lo)                               ranges narrower than 20:1 (or signed)
//   log     x = lo (hi/lo)^u                                   lo > 0 and hi/lo ≥ 20 (radii, roughness)
//   log1p   x = (1 + hi)^u − 1                                 lo = 0 and hi ≥ 100 (exponents up to 1e6)
// so that a step of the optimizer means the same relative change across decades.
//
// Mixtures (partitive, models/mixture.h): each lobe's parameters are named LABEL.KEY, LABEL the
// lobe's model name (with its position appended when a name occurs twice, e.g. ggx2), and the
// weights of lobes 2.. are free as LABEL.weight, relative to the first lobe's, in [1e-3, 1e3].
#pragma once

#include <string>
#include <vector>

#include "models/spec.h"

namespace ganzfeld::fit {

/// A range open at its lower end (ggx's alpha in (0, 1]) is searched from this fraction of its width.
inline constexpr double kOpenFloor = 1e-4;

enum class Mapping { linear, log, log1p };

struct FreeParameter {
  std::string name;  ///< "alpha", or "ggx.alpha" in a mixture
  double lo = 0.0, hi = 1.0, start = 0.0;
  Mapping mapping = Mapping::linear;
  double to_unit(double x) const;
  double from_unit(double u) const;
};

/// The parameter space of a model spec (single or mixture) with some parameters fixed.
class ParameterSpace {
 public:
  /// `spec`: the model and the start values; `fixed`: "KEY=VALUE" items (a choice by its name).
  /// Throws InputError: unknown or malformed --fixed item, a value out of range, a model with no
  /// free parameter left.
  ParameterSpace(const std::string& spec, const std::vector<std::string>& fixed);
  const std::vector<FreeParameter>& free() const { return free_; }
  /// The spec text with the free parameters at `x` (model units), fixed ones as given.
  std::string spec_at(const std::vector<double>& x) const;
  /// The start values (model units).
  std::vector<double> start() const;
  /// Every parameter of the spec, fixed and free, by name, from a canonical spec of the same model
  /// (how a report reads the truth back): "alpha" -> 0.3. Throws InputError on a different model.
  std::vector<std::pair<std::string, double>> values_of(const std::string& spec) const;

 private:
  /// One lobe: its canonical spec with the --fixed values (weight relative to the first lobe's);
  /// spec_at puts x into the free ones.
  struct LobeSpace {
    std::string label;  ///< the model's name, with the lobe's position when the name occurs twice
    SpecTerm term;
    std::vector<std::pair<std::string, int>> free_values;  ///< parameter name, index into x
    int weight_index = -1;                                 ///< free relative weight, lobes 2..
  };
  std::vector<LobeSpace> lobes_;
  std::vector<FreeParameter> free_;
};

/// The spec as the model it makes writes it (Model::spec() read back by parse_spec): each lobe in
/// the parametrization its model is in, weights normalized. Throws InputError for a spec
/// parse_model refuses.
Spec canonical_spec(const std::string& spec);

}  // namespace ganzfeld::fit
