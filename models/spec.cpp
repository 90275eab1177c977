#include "models/spec.h"

#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "models/mixture.h"
#include "util/error.h"

namespace ganzfeld {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t k = 0; k <= s.size(); ++k) {
    if (k == s.size() || s[k] == sep) {
      parts.push_back(s.substr(start, k - start));
      start = k + 1;
    }
  }
  return parts;
}

/// The parameter `key` of the model; throws InputError naming the model and its parameters.
const ParamInfo& find_param(const ModelInfo& info, const std::string& key) {
  std::string allowed;
  for (const auto& p : info.parameters) {
    if (p.name == key) return p;
    allowed += (allowed.empty() ? "" : ", ") + p.name;
  }
  throw InputError("unknown parameter '" + key + "' for model '" + info.name +
                   "'; allowed: " + (allowed.empty() ? "none" : allowed));
}

/// NAME[:KEY=VALUE,...] of one model. A data file's path is text up to the next ',' (it may
/// hold ':' after the first one).
ModelSpec parse_model_spec(const std::string& term) {
  const std::string spec = trim(term);
  if (spec.empty()) throw InputError("empty model spec; expected NAME[:KEY=VALUE,...], e.g. specular:alpha=8");
  const auto colon = spec.find(':');
  ModelSpec parsed{trim(spec.substr(0, colon))};
  const std::string& name = parsed.name;
  const ModelInfo& info = find_model(name);
  if (colon != std::string::npos) {
    std::vector<std::string> seen;
    for (const auto& item : split(spec.substr(colon + 1), ',')) {
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw InputError("malformed model spec '" + spec + "': expected KEY=VALUE, got '" + trim(item) + "'");
      const std::string key = trim(item.substr(0, eq));
      const std::string text = trim(item.substr(eq + 1));
      if (key == "file" && info.make_with_file) {  // a path, not a number
        if (!parsed.file.empty()) throw InputError("parameter 'file' given twice in '" + spec + "'");
        if (text.empty()) throw InputError(name + ": file= needs a path");
        parsed.file = text;
        continue;
      }
      const ParamInfo* param = &find_param(info, key);
      for (const auto& s : seen)
        if (s == key) throw InputError("parameter '" + key + "' given twice in '" + spec + "'");
      seen.push_back(key);
      double value;
      if (param->type == ParamType::choice) value = parse_choice(info, *param, text);
      else if (!parse_number(text, value)) throw InputError(name + ": " + key + "='" + text + "' is not a number");
      validate_param(info, *param, value);
      parsed.values[key] = value;
    }
  }
  if (info.make_with_file && parsed.file.empty() && !info.file_optional)
    throw InputError(name + " needs file=PATH (the measured data), e.g. " + name + ":file=data.binary");
  return parsed;
}

/// Mixture terms are separated by '+', except the '+' of an exponent such as 1e+3.
std::vector<std::string> split_terms(const std::string& s) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t k = 0; k <= s.size(); ++k) {
    const bool exponent_sign = k >= 2 && k < s.size() && (s[k - 1] == 'e' || s[k - 1] == 'E') &&
                               (std::isdigit(static_cast<unsigned char>(s[k - 2])) || s[k - 2] == '.');
    if (k == s.size() || (s[k] == '+' && !exponent_sign)) {
      parts.push_back(s.substr(start, k - start));
      start = k + 1;
    }
  }
  return parts;
}

/// What n weights summing to `total` are divided by: 1 when they sum to 1 within rounding.
double normalizing_divisor(double total, std::size_t n) {
  const double rounding = 4.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon();
  return std::abs(total - 1.0) <= rounding ? 1.0 : total;
}

}  // namespace

bool Spec::names_file() const {
  for (const SpecTerm& term : terms)
    if (!term.model.file.empty()) return true;
  return false;
}

Spec parse_spec(const std::string& text) {
  Spec spec;
  double total = 0.0;
  for (const auto& term_text : split_terms(text)) {
    const std::string term = trim(term_text);
    if (term.empty()) throw InputError("malformed mixture '" + text + "': empty term around '+'");
    double weight = 1.0;
    std::string body = term;
    const auto star = term.find('*');
    if (star != std::string::npos) {
      const std::string w = trim(term.substr(0, star));
      if (!parse_number(w, weight))
        throw InputError("malformed mixture weight '" + w + "' in '" + text + "'; expected a number");
      if (!std::isfinite(weight) || weight <= 0.0)
        throw InputError("mixture weight " + w + " in '" + text + "' is not allowed; weights must be finite and > 0");
      body = term.substr(star + 1);
    }
    spec.terms.push_back({weight, parse_model_spec(body)});
    total += weight;
  }
  if (!std::isfinite(total))  // each weight finite, their sum not: normalizing would make them NaN
    throw InputError("mixture weights in '" + text +
                     "' sum to more than the largest number (about 1.8e308); "
                     "scale them down (only their ratios matter)");
  const double divisor = normalizing_divisor(total, spec.terms.size());
  for (SpecTerm& term : spec.terms) term.weight /= divisor;
  return spec;
}

std::vector<std::string> given_parameters(const ModelSpec& spec) {
  const ModelInfo& info = find_model(spec.name);
  const auto given = [&](const std::string& name) { return spec.values.count(name) > 0; };
  std::vector<std::string> names;
  for (const ParamInfo& p : info.parameters) {
    if (!p.alternative_of.empty() && !given(p.alternative_of)) continue;  // in that parameter's place
    if (given(p.name)) {
      names.push_back(p.name);
    } else {
      for (const ParamInfo& alternative : info.parameters)
        if (alternative.alternative_of == p.name && given(alternative.name)) names.push_back(alternative.name);
    }
  }
  if (names.size() != spec.values.size())
    throw std::logic_error("given_parameters: a value of '" + spec.name + "' is no registered parameter");
  return names;
}

std::string spec_text(const ModelSpec& spec) {
  const ModelInfo& info = find_model(spec.name);
  std::vector<std::string> items;
  if (!spec.file.empty()) items.push_back("file=" + spec.file);
  for (const std::string& name : given_parameters(spec))
    items.push_back(name + "=" + value_text(find_param(info, name), spec.values.at(name)));
  std::string text = spec.name;
  for (std::size_t k = 0; k < items.size(); ++k) text += (k ? "," : ":") + items[k];
  return text;
}

std::string spec_text(const Spec& spec) {
  if (spec.terms.size() == 1) return spec_text(spec.terms.front().model);
  std::string text;
  for (const SpecTerm& term : spec.terms)
    text += (text.empty() ? "" : " + ") + format_number(term.weight) + "*" + spec_text(term.model);
  return text;
}

ModelPtr make_model(const ModelSpec& spec) {
  const ModelInfo& info = find_model(spec.name);
  ParamValues values;
  for (const auto& p : info.parameters)
    if (!p.optional) values[p.name] = p.default_value;
  for (const auto& [key, value] : spec.values) {
    validate_param(info, find_param(info, key), value);
    values[key] = value;
  }
  if (info.make_with_file) return info.make_with_file(spec.file, values);
  return info.make(values);
}

void normalize_weights(std::vector<Lobe>& lobes) {
  double total = 0.0;
  for (const auto& lobe : lobes) total += lobe.weight;
  const double divisor = normalizing_divisor(total, lobes.size());
  for (auto& lobe : lobes) lobe.weight /= divisor;
}

std::vector<Lobe> make_lobes(const Spec& spec) {
  std::vector<Lobe> lobes;
  for (const SpecTerm& term : spec.terms) lobes.push_back({term.weight, make_model(term.model)});
  return lobes;
}

ModelPtr make_model(const Spec& spec) {
  auto lobes = make_lobes(spec);
  if (lobes.size() == 1) return lobes.front().model;
  return std::make_shared<Mixture>(std::move(lobes));
}

ModelPtr parse_model(const std::string& text) { return make_model(parse_spec(text)); }

std::vector<Lobe> parse_lobes(const std::string& text) { return make_lobes(parse_spec(text)); }

std::string spec_without_paths(const std::string& text) {
  Spec spec = parse_spec(text);
  for (SpecTerm& term : spec.terms) term.model.file.clear();
  return spec_text(spec);
}

ModelSpec with_parameter(const Spec& spec, const std::string& key, double value) {
  if (spec.is_mixture())
    throw InputError({Named{key}, " applies to a single model, not to the mixture '" + spec_text(spec) + "'"});
  ModelSpec model = spec.terms.front().model;
  const ModelInfo& info = find_model(model.name);
  const ParamInfo* param = nullptr;
  std::string known;
  for (const ParamInfo& p : info.parameters) {
    if (p.name == key) param = &p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  if (!param)
    throw InputError({"model '" + model.name + "' has no parameter " + key + " for ", Named{key},
                      "; its parameters: " + (known.empty() ? "none" : known)});
  const std::string& principal = param->alternative_of.empty() ? param->name : param->alternative_of;
  for (const ParamInfo& p : info.parameters)
    if (p.name == principal || p.alternative_of == principal) model.values.erase(p.name);
  validate_param(info, *param, value);
  model.values[key] = value;
  return model;
}

}  // namespace ganzfeld
