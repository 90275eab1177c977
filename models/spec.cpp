#include "models/spec.h"

#include <cctype>
#include <cmath>
#include <limits>
#include <cstdlib>

#include "util/error.h"
#include "models/mixture.h"
#include "models/registry.h"

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

/// Parses a whole string as a double (accepts "nan"/"inf" so they can be refused by range).
bool parse_double(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

ModelPtr parse_single(const std::string& spec_text) {
  const std::string spec = trim(spec_text);
  if (spec.empty()) throw InputError("empty model spec; expected NAME[:KEY=VALUE,...], e.g. specular:alpha=8");
  const auto colon = spec.find(':');
  const std::string name = trim(spec.substr(0, colon));
  const ModelInfo& info = find_model(name);

  ParamValues values;
  for (const auto& p : info.parameters)
    if (!p.optional) values[p.name] = p.default_value;
  std::string file;
  if (colon != std::string::npos) {
    std::vector<std::string> seen;
    for (const auto& item : split(spec.substr(colon + 1), ',')) {
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw InputError("malformed model spec '" + spec + "': expected KEY=VALUE, got '" + trim(item) + "'");
      const std::string key = trim(item.substr(0, eq));
      const std::string text = trim(item.substr(eq + 1));
      if (key == "file" && info.make_with_file) {  // a path, not a number
        if (!file.empty()) throw InputError("parameter 'file' given twice in '" + spec + "'");
        if (text.empty()) throw InputError(name + ": file= needs a path");
        file = text;
        continue;
      }
      const ParamInfo* param = nullptr;
      std::string allowed;
      for (const auto& p : info.parameters) {
        if (p.name == key) param = &p;
        allowed += (allowed.empty() ? "" : ", ") + p.name;
      }
      if (!param)
        throw InputError("unknown parameter '" + key + "' for model '" + name + "'; allowed: " +
                         (allowed.empty() ? "none" : allowed));
      for (const auto& s : seen)
        if (s == key) throw InputError("parameter '" + key + "' given twice in '" + spec + "'");
      seen.push_back(key);
      double value;
      if (param->type == ParamType::choice)
        value = parse_choice(info, *param, text);
      else if (!parse_double(text, value))
        throw InputError(name + ": " + key + "='" + text + "' is not a number");
      validate_param(info, *param, value);
      values[key] = value;
    }
  }
  if (info.make_with_file) {
    if (file.empty() && !info.file_optional)
      throw InputError(name + " needs file=PATH (the measured data), e.g. " + name + ":file=data.binary");
    return info.make_with_file(file, values);
  }
  return info.make(values);
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

}  // namespace

std::vector<Lobe> parse_lobes(const std::string& spec) {
  std::vector<Lobe> lobes;
  for (const auto& term_text : split_terms(spec)) {
    const std::string term = trim(term_text);
    if (term.empty()) throw InputError("malformed mixture '" + spec + "': empty term around '+'");
    double weight = 1.0;
    std::string body = term;
    const auto star = term.find('*');
    if (star != std::string::npos) {
      const std::string w = trim(term.substr(0, star));
      if (!parse_double(w, weight))
        throw InputError("malformed mixture weight '" + w + "' in '" + spec + "'; expected a number");
      if (!std::isfinite(weight) || weight <= 0.0)
        throw InputError("mixture weight " + w + " in '" + spec + "' is not allowed; weights must be finite and > 0");
      body = term.substr(star + 1);
    }
    lobes.push_back({weight, parse_single(body)});
  }
  double total = 0.0;
  for (const Lobe& lobe : lobes) total += lobe.weight;
  if (!std::isfinite(total))  // each weight finite, their sum not: normalizing would make them NaN
    throw InputError("mixture weights in '" + spec +
                     "' sum to more than the largest number (about 1.8e308); "
                     "scale them down (only their ratios matter)");
  normalize_weights(lobes);
  return lobes;
}

void normalize_weights(std::vector<Lobe>& lobes) {
  double total = 0.0;
  for (const auto& lobe : lobes) total += lobe.weight;
  const double rounding = 4.0 * static_cast<double>(lobes.size()) * std::numeric_limits<double>::epsilon();
  if (std::abs(total - 1.0) <= rounding) return;
  for (auto& lobe : lobes) lobe.weight /= total;
}

std::string spec_without_paths(const std::string& spec) {
  std::string out;
  const std::vector<std::string> terms = split_terms(spec);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    const std::string& term = terms[t];
    const auto colon = term.find(':');  // a path never holds ',' or '+', but may hold ':' after this one
    std::string kept = term.substr(0, colon);
    std::string items;
    if (colon != std::string::npos)
      for (const std::string& item : split(term.substr(colon + 1), ','))
        if (trim(item.substr(0, item.find('='))) != "file") items += (items.empty() ? "" : ",") + item;
    out += (t ? "+" : "") + kept + (items.empty() ? "" : ":" + items);
  }
  return out;
}

std::string with_parameter(const std::string& spec, const std::string& key, double value) {
  const std::vector<std::string> terms = split_terms(spec);
  if (terms.size() != 1)
    throw InputError("--" + key + " applies to a single model, not to the mixture '" + spec + "'");
  const std::string& term = terms.front();
  const auto colon = term.find(':');
  const std::string name = trim(term.substr(0, colon));
  std::string known;
  bool has = false;
  for (const ParamInfo& p : find_model(name).parameters) {
    has = has || p.name == key;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  if (!has)
    throw InputError("model '" + name + "' has no parameter " + key + " for --" + key + "; its parameters: " +
                     (known.empty() ? "none" : known));
  std::string items;  // the spec's items without the roughness alternatives the flag replaces
  if (colon != std::string::npos)
    for (const std::string& item : split(term.substr(colon + 1), ',')) {
      const std::string k = trim(item.substr(0, item.find('=')));
      if (k != "alpha" && k != "roughness" && k != "alpha_x" && k != "alpha_y") items += item + ",";
    }
  return name + ":" + items + key + "=" + format_number(value);
}

ModelPtr parse_model(const std::string& spec) {
  auto lobes = parse_lobes(spec);
  if (lobes.size() == 1) return lobes.front().model;
  return std::make_shared<Mixture>(std::move(lobes));
}

}  // namespace ganzfeld
