// The catalogue of models: names, parameter tables (Mitsuba-style: name, type, range, default,
// meaning), traits, and the factory that turns validated parameters into a Model.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld {

/// choice: the spec gives one of ParamInfo::choices by name; the value is its index.
enum class ParamType { real, integer, choice };

struct ParamInfo {
  std::string name;
  ParamType type = ParamType::real;
  double min = 0.0;  ///< inclusive (exclusive with min_exclusive)
  double max = 0.0;  ///< inclusive
  double default_value = 0.0;
  std::string meaning;
  std::vector<std::string> choices{};  ///< the names of a choice parameter, by index
  /// Left out of ParamValues unless the spec gives it, so a factory can tell alternatives
  /// apart (ggx's alpha and roughness); default_value is then what the factory uses when none
  /// of the alternatives is given.
  bool optional = false;
  bool min_exclusive = false;  ///< the range is (min, max]: e.g. a roughness that must be > 0
  /// The parameter this one stands in for (ggx's roughness for alpha, hvd-empirical's rsu and
  /// rsv for rs): a spec gives one of them; spec_text writes it in that parameter's place.
  std::string alternative_of{};
};

using ParamValues = std::map<std::string, double>;

struct ModelInfo {
  std::string name;
  std::string summary;
  std::string source;  ///< paper and section the model comes from
  std::vector<ParamInfo> parameters;
  Traits traits;
  std::vector<std::string> closed_forms;             ///< ids of printed closed forms checked by `verify`
  std::function<ModelPtr(const ParamValues&)> make;  ///< params complete and validated
  /// Set instead of `make` for measured models: the spec carries `file=PATH` (required), which
  /// is passed as text; the other parameters as usual.
  std::function<ModelPtr(const std::string& file, const ParamValues&)> make_with_file = nullptr;
  /// With make_with_file: `file=PATH` may be left out (the model has a built-in default and
  /// make_with_file receives an empty path); file_meaning says what the file holds.
  bool file_optional = false;
  std::string file_meaning = "the measured data file";
};

/// Model families register themselves here (one function per family, in its own file).
void register_hvd_models(std::vector<ModelInfo>& catalogue);                // models/hvd.cpp (Edwards et al.)
void register_classic_models(std::vector<ModelInfo>& catalogue);            // models/classic.cpp (Walker's survey)
void register_measured_models(std::vector<ModelInfo>& catalogue);           // models/measured.cpp (MERL, tabulated)
void register_he_torrance_models(std::vector<ModelInfo>& catalogue);        // models/he_torrance.cpp
void register_blinn_dusty_models(std::vector<ModelInfo>& catalogue);        // models/blinn_dusty.cpp
void register_beard_maxwell_models(std::vector<ModelInfo>& catalogue);      // models/beard_maxwell.cpp
void register_poulin_fournier_models(std::vector<ModelInfo>& catalogue);    // models/poulin_fournier.cpp
void register_ggx_models(std::vector<ModelInfo>& catalogue);                // models/ggx.cpp (microfacets, Smith G2)
void register_charlie_models(std::vector<ModelInfo>& catalogue);            // models/charlie.cpp (sheen)
void register_ashikhmin_shirley_models(std::vector<ModelInfo>& catalogue);  // models/ashikhmin_shirley.cpp
void register_schlick_models(std::vector<ModelInfo>& catalogue);            // models/schlick.cpp (Schlick 1994)
void register_kajiya_models(std::vector<ModelInfo>& catalogue);             // models/kajiya.cpp (fibres)

/// Every registered model, in presentation order.
const std::vector<ModelInfo>& model_catalogue();
/// Throws InputError naming the unknown model and listing the known ones.
const ModelInfo& find_model(const std::string& name);

/// Validates one value against its ParamInfo; throws InputError naming model, key, value and
/// the allowed range.
void validate_param(const ModelInfo& model, const ParamInfo& param, double value);
/// What a parameter allows, as validate_param says it: "a real number in (0, 1]", "one of a, b".
std::string allowed_values(const ParamInfo& param);
/// The index of `text` among a choice parameter's names; throws InputError naming model, key,
/// the text and the allowed names.
double parse_choice(const ModelInfo& model, const ParamInfo& param, const std::string& text);

/// Shortest text that round-trips the double (used in canonical spec strings).
std::string format_number(double value);
/// Reads a whole text as a number, as a spec's values and weights are read (format_number's texts
/// among them); accepts "nan" and "inf" so that a range can refuse them. False when the text is not one.
bool parse_number(const std::string& text, double& value);
/// A parameter's value as a spec writes it: a choice by name, else format_number.
std::string value_text(const ParamInfo& param, double value);

}  // namespace ganzfeld
