// Spec strings: NAME[:KEY=VALUE[,KEY=VALUE...]] and partitive mixtures
// "0.7*minnaert:xi=1 + 0.3*specular:alpha=8" (K&P, "partitive mixture of BRDFs").
//
// The grammar lives here alone: parse_spec reads a text into a Spec, checked against the
// registry's parameter tables (nothing is built, no file is read); spec_text writes a Spec back in
// the registry's parameter order; make_model builds it. A model's canonical spec, its identity and
// the cache's key, is spec_text of the parameters that define it (Model::spec), so
// parse_spec(model.spec()) gives those parameters back and spec_text of that is model.spec().
#pragma once

#include <string>
#include <vector>

#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

/// One model of a spec: its registered name, the parameters the text gives (validated; a choice
/// as its index) and, for a measured model, the path of its data file ("" when not given).
struct ModelSpec {
  std::string name;
  ParamValues values{};
  std::string file{};
  friend bool operator==(const ModelSpec&, const ModelSpec&) = default;
};

/// One weighted term of a partitive mixture.
struct SpecTerm {
  double weight = 1.0;
  ModelSpec model;
  friend bool operator==(const SpecTerm&, const SpecTerm&) = default;
};

/// A parsed spec: one term for a plain model, several for a mixture; the weights sum to 1.
struct Spec {
  std::vector<SpecTerm> terms;
  bool is_mixture() const { return terms.size() > 1; }
  /// Whether a term names a data file (file=PATH).
  bool names_file() const;
  friend bool operator==(const Spec&, const Spec&) = default;
};

/// Parses and validates a spec against the registry (model names, parameter names, ranges,
/// choices, a required data file); throws InputError with a one-line message on bad input.
Spec parse_spec(const std::string& text);

/// NAME[:file=PATH][,KEY=VALUE...]: the given parameters in the registry's order (an
/// alternative that stands in for an absent parameter, ParamInfo::alternative_of, in that
/// parameter's place), numbers as format_number, choices by name.
std::string spec_text(const ModelSpec& spec);
/// The names of the parameters the spec gives, in spec_text's order.
std::vector<std::string> given_parameters(const ModelSpec& spec);
/// A plain model's spec_text, or "W1*TERM1 + W2*TERM2 + ..." for a mixture.
std::string spec_text(const Spec& spec);

/// Builds the model: the registry's defaults for what the spec does not give (reads its data
/// file). Throws InputError for a parameter the model does not have or a value out of range.
ModelPtr make_model(const ModelSpec& spec);

/// One weighted lobe of a (possibly single-lobe) spec; weights are normalized to sum to 1.
struct Lobe {
  double weight;
  ModelPtr model;
};
/// Divides the weights by their sum, unless they already sum to 1 within rounding (4 n ulps):
/// normalizing normalized weights changes nothing, so a mixture's canonical spec (whose printed
/// weights sum to 1 only within rounding) parses back to itself (fuzz/spec_fuzz.cpp).
void normalize_weights(std::vector<Lobe>& lobes);

/// The lobes of a spec (a plain model is one lobe of weight 1). Tables are baked per lobe.
std::vector<Lobe> make_lobes(const Spec& spec);
/// A plain model, or the Mixture of the lobes.
ModelPtr make_model(const Spec& spec);

/// make_model(parse_spec(text)).
ModelPtr parse_model(const std::string& text);
/// make_lobes(parse_spec(text)).
std::vector<Lobe> parse_lobes(const std::string& text);

/// The spec with every data file's path left out: what identifies a measured model apart from
/// where its data file lies (Model::content_digest identifies the data). Nothing is read.
/// "merl:file=a.binary,channel=3,lookup=1" -> "merl:channel=3,lookup=1".
std::string spec_without_paths(const std::string& text);

/// The plain model of `spec` with the parameter `key` set to `value` in place of `key` and
/// its alternatives (ParamInfo::alternative_of): ggx:roughness=0.2,f0=0.04 with ("alpha", 0.5)
/// -> ggx:alpha=0.5,f0=0.04. Throws InputError for a mixture, a model without `key` or a value
/// out of its range.
ModelSpec with_parameter(const Spec& spec, const std::string& key, double value);

}  // namespace ganzfeld
