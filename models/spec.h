// Spec strings: NAME[:KEY=VALUE[,KEY=VALUE...]] and partitive mixtures
// "0.7*minnaert:xi=1 + 0.3*specular:alpha=8" (K&P, "partitive mixture of BRDFs").
#pragma once

#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld {

/// Parses and validates a spec; throws InputError with a one-line message on bad input.
ModelPtr parse_model(const std::string& spec);

/// One weighted lobe of a (possibly single-lobe) spec; weights are normalized to sum to 1.
struct Lobe {
  double weight;
  ModelPtr model;
};
/// Divides the weights by their sum, unless they already sum to 1 within rounding (4 n ulps):
/// normalizing normalized weights changes nothing, so a mixture's canonical spec (whose printed
/// weights sum to 1 only within rounding) parses back to itself (found by fuzz/spec_fuzz.cpp).
void normalize_weights(std::vector<Lobe>& lobes);

/// The lobes of a spec (a plain model is one lobe of weight 1). Tables are baked per lobe.
std::vector<Lobe> parse_lobes(const std::string& spec);

/// The spec with every `file=PATH` item removed, as text (nothing is parsed or read): what
/// identifies a measured model apart from where its data file lies; Model::content_digest
/// identifies the data. "merl:file=a.binary,channel=3,lookup=1" -> "merl:channel=3,lookup=1".
std::string spec_without_paths(const std::string& spec);

/// The single-model spec with its roughness (alpha, roughness, alpha_x, alpha_y items) replaced
/// by key=value: "ggx:roughness=0.2,f0=0.04" with ("alpha", 0.5) -> "ggx:f0=0.04,alpha=0.5".
/// Throws InputError for a mixture or a model without a parameter named `key` (nothing is
/// validated beyond that: parse_model judges the value).
std::string with_parameter(const std::string& spec, const std::string& key, double value);

}  // namespace ganzfeld
