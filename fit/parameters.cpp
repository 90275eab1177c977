#include "fit/parameters.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld::fit {

namespace {

/// Relative mixture weights (lobe l over lobe 1) are searched in [1/kWeightSpan, kWeightSpan].
constexpr double kWeightSpan = 1e3;

/// The registry's entry for `key` of model `info`, or nothing (file=, or not a parameter).
const ParamInfo* param_info(const ModelInfo& info, const std::string& key) {
  for (const ParamInfo& p : info.parameters)
    if (p.name == key) return &p;
  return nullptr;
}

Mapping mapping_for(double lo, double hi) {
  if (lo > 0.0 && hi / lo >= 20.0) return Mapping::log;
  if (lo == 0.0 && hi >= 100.0) return Mapping::log1p;
  return Mapping::linear;
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

}  // namespace

double FreeParameter::to_unit(double x) const {
  double u = 0.0;
  switch (mapping) {
    case Mapping::linear: u = (x - lo) / (hi - lo); break;
    case Mapping::log: u = std::log(x / lo) / std::log(hi / lo); break;
    case Mapping::log1p: u = std::log1p(x) / std::log1p(hi); break;
  }
  return std::clamp(u, 0.0, 1.0);
}

double FreeParameter::from_unit(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  double x = 0.0;
  switch (mapping) {
    case Mapping::linear: x = lo + u * (hi - lo); break;
    case Mapping::log: x = lo * std::exp(u * std::log(hi / lo)); break;
    case Mapping::log1p: x = std::expm1(u * std::log1p(hi)); break;
  }
  return std::clamp(x, lo, hi);  // exp/log round trips may overshoot an end by an ulp
}

std::vector<SpecTerm> spec_terms(const std::string& spec) {
  std::vector<SpecTerm> terms;
  for (const Lobe& lobe : parse_lobes(spec)) {
    const std::string canonical = lobe.model->spec();
    SpecTerm term;
    term.weight = lobe.weight;
    const auto colon = canonical.find(':');
    term.name = canonical.substr(0, colon);
    // Canonical items are KEY=VALUE separated by ','; a file path holds no ',' (models/measured.h).
    std::size_t start = colon == std::string::npos ? canonical.size() : colon + 1;
    while (start < canonical.size()) {
      const auto comma = std::min(canonical.find(',', start), canonical.size());
      const std::string item = canonical.substr(start, comma - start);
      const auto eq = item.find('=');
      term.items.emplace_back(item.substr(0, eq), eq == std::string::npos ? "" : item.substr(eq + 1));
      start = comma + 1;
    }
    terms.push_back(std::move(term));
  }
  return terms;
}

ParameterSpace::ParameterSpace(const std::string& spec, const std::vector<std::string>& fixed) {
  const std::vector<SpecTerm> terms = spec_terms(spec);
  std::map<std::string, int> count;
  for (const SpecTerm& t : terms) ++count[t.name];
  const bool mixture = terms.size() > 1;
  for (std::size_t l = 0; l < terms.size(); ++l) {
    LobeItems lobe;
    lobe.name = terms[l].name;
    lobe.label = count[lobe.name] > 1 ? lobe.name + std::to_string(l + 1) : lobe.name;
    lobe.weight = terms[l].weight / terms.front().weight;
    for (const auto& [key, text] : terms[l].items) lobe.items.push_back({key, text, -1});
    lobes_.push_back(std::move(lobe));
  }
  auto qualified = [&](const LobeItems& lobe, const std::string& key) {
    return mixture ? lobe.label + "." + key : key;
  };

  // --fixed items: each names a parameter of the model (or a lobe's weight) and a value in range.
  std::map<std::string, bool> is_fixed;
  for (const std::string& item : fixed) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({Named{"fixed"}, " '" + item + "' is not KEY=VALUE"});
    const std::string name = item.substr(0, eq), text = item.substr(eq + 1);
    bool found = false;
    std::string known;
    for (std::size_t l = 0; l < lobes_.size() && !found; ++l) {
      LobeItems& lobe = lobes_[l];
      const ModelInfo& info = find_model(lobe.name);
      if (mixture && l > 0) {
        known += (known.empty() ? "" : ", ") + lobe.label + ".weight";
        if (name == lobe.label + ".weight") {
          double w;
          if (!parse_number(text, w) || !std::isfinite(w) || w <= 0.0)
            throw InputError({Named{"fixed", item}, ": a weight must be a finite number > 0 (relative to the first lobe's)"});
          lobe.weight = w;
          is_fixed[name] = found = true;
          break;
        }
      }
      for (const ParamInfo& p : info.parameters) {
        known += (known.empty() ? "" : ", ") + qualified(lobe, p.name);
        if (qualified(lobe, p.name) != name) continue;
        std::string value_text = text;
        if (p.type == ParamType::choice) {
          parse_choice(info, p, text);
        } else {
          double v;
          if (!parse_number(text, v)) throw InputError({Named{"fixed", item}, ": '" + text + "' is not a number"});
          validate_param(info, p, v);
          value_text = format_number(v);
        }
        auto it = std::find_if(lobe.items.begin(), lobe.items.end(), [&](const Item& x) { return x.key == p.name; });
        if (it == lobe.items.end())
          lobe.items.push_back({p.name, value_text, -1});
        else
          it->text = value_text;
        is_fixed[name] = found = true;
        break;
      }
    }
    if (!found)
      throw InputError({Named{"fixed"}, " names unknown parameter '" + name + "'; the model's parameters: " +
                                                (known.empty() ? "none" : known)});
  }

  // Free: the real-valued items not fixed, then the weights of lobes 2.. not fixed.
  std::string integral;
  for (LobeItems& lobe : lobes_) {
    const ModelInfo& info = find_model(lobe.name);
    for (Item& item : lobe.items) {
      const ParamInfo* p = param_info(info, item.key);
      const std::string name = qualified(lobe, item.key);
      if (!p) continue;
      if (p->type != ParamType::real) {
        integral += (integral.empty() ? "" : ", ") + name;
        continue;
      }
      if (is_fixed.count(name)) continue;
      double value = 0.0;
      parse_number(item.text, value);
      FreeParameter f;
      f.name = name;
      f.lo = p->min_exclusive ? p->min + kOpenFloor * (p->max - p->min) : p->min;
      f.hi = p->max;
      f.start = std::clamp(value, f.lo, f.hi);
      f.mapping = mapping_for(f.lo, f.hi);
      item.free_index = static_cast<int>(free_.size());
      free_.push_back(f);
    }
  }
  for (std::size_t l = 1; l < lobes_.size(); ++l) {
    LobeItems& lobe = lobes_[l];
    const std::string name = lobe.label + ".weight";
    if (is_fixed.count(name)) continue;
    FreeParameter f{name, 1.0 / kWeightSpan, kWeightSpan, std::clamp(lobe.weight, 1.0 / kWeightSpan, kWeightSpan),
                    Mapping::log};
    lobe.weight_index = static_cast<int>(free_.size());
    free_.push_back(f);
  }
  if (free_.empty())
    throw InputError({"model '" + spec + "' has no free parameter to fit" +
                          (integral.empty() ? std::string(" (it has no real-valued parameter)")
                                            : " (" + integral + ": integers and choices are not fitted)") +
                          (fixed.empty() ? "" : " once "),
                      fixed.empty() ? InputError::Piece{""} : InputError::Piece{Named{"fixed"}},
                      fixed.empty() ? "" : " ones are set"});
  // The start must make a model: --fixed may contradict the rest (ggx: roughness beside alpha).
  try {
    parse_model(spec_at(start()));
  } catch (const InputError& e) {
    throw InputError({"the start point with ", Named{"fixed"}, std::string(" is not a model: ") + e.what()});
  }
}

std::vector<double> ParameterSpace::start() const {
  std::vector<double> x;
  for (const FreeParameter& f : free_) x.push_back(f.start);
  return x;
}

std::string ParameterSpace::spec_at(const std::vector<double>& x) const {
  std::string s;
  for (std::size_t l = 0; l < lobes_.size(); ++l) {
    const LobeItems& lobe = lobes_[l];
    if (lobes_.size() > 1) {
      const double w = lobe.weight_index >= 0 ? x[lobe.weight_index] : lobe.weight;
      s += (l ? " + " : "") + format_number(w) + "*";
    }
    s += lobe.name;
    for (std::size_t k = 0; k < lobe.items.size(); ++k) {
      const Item& item = lobe.items[k];
      s += (k ? "," : ":") + item.key + "=" + (item.free_index >= 0 ? format_number(x[item.free_index]) : item.text);
    }
  }
  return s;
}

std::vector<std::pair<std::string, double>> ParameterSpace::values_of(const std::string& spec) const {
  const std::vector<SpecTerm> terms = spec_terms(spec);
  if (terms.size() != lobes_.size())
    throw InputError("'" + spec + "' has " + std::to_string(terms.size()) + " lobes; the fitted model has " +
                     std::to_string(lobes_.size()));
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t l = 0; l < terms.size(); ++l) {
    if (terms[l].name != lobes_[l].name)
      throw InputError("'" + spec + "' is not a " + lobes_[l].name + " where the fitted model is");
    for (const auto& [key, text] : terms[l].items) {
      double v;
      if (parse_number(text, v)) out.emplace_back(lobes_.size() > 1 ? lobes_[l].label + "." + key : key, v);
    }
    if (l > 0) out.emplace_back(lobes_[l].label + ".weight", terms[l].weight / terms.front().weight);
  }
  return out;
}

}  // namespace ganzfeld::fit
