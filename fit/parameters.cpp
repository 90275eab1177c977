#include "fit/parameters.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld::fit {

namespace {

/// Relative mixture weights (lobe l over lobe 1) are searched in [1/kWeightSpan, kWeightSpan].
constexpr double kWeightSpan = 1e3;

/// The registry's entry for `key`, a parameter of model `info`.
const ParamInfo& param_info(const ModelInfo& info, const std::string& key) {
  const auto named = [&](const ParamInfo& p) { return p.name == key; };
  return *std::find_if(info.parameters.begin(), info.parameters.end(), named);
}

Mapping mapping_for(double lo, double hi) {
  if (lo > 0.0 && hi / lo >= 20.0) return Mapping::log;
  if (lo == 0.0 && hi >= 100.0) return Mapping::log1p;
  return Mapping::linear;
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

Spec canonical_spec(const std::string& spec) { return parse_spec(parse_model(spec)->spec()); }

ParameterSpace::ParameterSpace(const std::string& spec, const std::vector<std::string>& fixed) {
  const Spec canonical = canonical_spec(spec);
  std::map<std::string, int> count;
  for (const SpecTerm& t : canonical.terms) ++count[t.model.name];
  const bool mixture = canonical.is_mixture();
  for (std::size_t l = 0; l < canonical.terms.size(); ++l) {
    LobeSpace lobe;
    lobe.term = canonical.terms[l];
    const std::string& name = lobe.term.model.name;
    lobe.label = count[name] > 1 ? name + std::to_string(l + 1) : name;
    lobe.term.weight /= canonical.terms.front().weight;
    lobes_.push_back(std::move(lobe));
  }
  auto qualified = [&](const LobeSpace& lobe, const std::string& key) {
    return mixture ? lobe.label + "." + key : key;
  };

  // --fixed items: each names a parameter of the model (or a lobe's weight) and a value in range.
  std::map<std::string, bool> is_fixed;
  for (const std::string& item : fixed) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError({Named{"fixed"}, " '" + item + "' is not KEY=VALUE"});
    const std::string name = item.substr(0, eq), text = item.substr(eq + 1);
    bool found = false;
    std::string known;
    for (std::size_t l = 0; l < lobes_.size() && !found; ++l) {
      LobeSpace& lobe = lobes_[l];
      const ModelInfo& info = find_model(lobe.term.model.name);
      if (mixture && l > 0) {
        known += (known.empty() ? "" : ", ") + lobe.label + ".weight";
        if (name == lobe.label + ".weight") {
          double w;
          if (!parse_number(text, w) || !std::isfinite(w) || w <= 0.0)
            throw InputError(
                {Named{"fixed", item}, ": a weight must be a finite number > 0 (relative to the first lobe's)"});
          lobe.term.weight = w;
          is_fixed[name] = found = true;
          break;
        }
      }
      for (const ParamInfo& p : info.parameters) {
        known += (known.empty() ? "" : ", ") + qualified(lobe, p.name);
        if (qualified(lobe, p.name) != name) continue;
        double v;
        if (p.type == ParamType::choice) {
          v = parse_choice(info, p, text);
        } else {
          if (!parse_number(text, v)) throw InputError({Named{"fixed", item}, ": '" + text + "' is not a number"});
          validate_param(info, p, v);
        }
        lobe.term.model.values[p.name] = v;
        is_fixed[name] = found = true;
        break;
      }
    }
    if (!found)
      throw InputError({Named{"fixed"}, " names unknown parameter '" + name +
                                            "'; the model's parameters: " + (known.empty() ? "none" : known)});
  }

  // Free: the real-valued parameters not fixed, then the weights of lobes 2.. not fixed.
  std::string integral;
  for (LobeSpace& lobe : lobes_) {
    const ModelInfo& info = find_model(lobe.term.model.name);
    for (const std::string& key : given_parameters(lobe.term.model)) {
      const ParamInfo& p = param_info(info, key);
      const std::string name = qualified(lobe, key);
      if (p.type != ParamType::real) {
        integral += (integral.empty() ? "" : ", ") + name;
        continue;
      }
      if (is_fixed.count(name)) continue;
      FreeParameter f;
      f.name = name;
      f.lo = p.min_exclusive ? p.min + kOpenFloor * (p.max - p.min) : p.min;
      f.hi = p.max;
      f.start = std::clamp(lobe.term.model.values.at(key), f.lo, f.hi);
      f.mapping = mapping_for(f.lo, f.hi);
      lobe.free_values.emplace_back(key, static_cast<int>(free_.size()));
      free_.push_back(f);
    }
  }
  for (std::size_t l = 1; l < lobes_.size(); ++l) {
    LobeSpace& lobe = lobes_[l];
    const std::string name = lobe.label + ".weight";
    if (is_fixed.count(name)) continue;
    FreeParameter f{name, 1.0 / kWeightSpan, kWeightSpan, std::clamp(lobe.term.weight, 1.0 / kWeightSpan, kWeightSpan),
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
  Spec spec;
  for (const LobeSpace& lobe : lobes_) {
    SpecTerm term = lobe.term;
    for (const auto& [key, index] : lobe.free_values) term.model.values[key] = x[index];
    if (lobe.weight_index >= 0) term.weight = x[lobe.weight_index];
    spec.terms.push_back(std::move(term));
  }
  return spec_text(spec);
}

std::vector<std::pair<std::string, double>> ParameterSpace::values_of(const std::string& spec) const {
  const Spec canonical = canonical_spec(spec);
  if (canonical.terms.size() != lobes_.size())
    throw InputError("'" + spec + "' has " + std::to_string(canonical.terms.size()) + " lobes; the fitted model has " +
                     std::to_string(lobes_.size()));
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t l = 0; l < canonical.terms.size(); ++l) {
    const ModelSpec& model = canonical.terms[l].model;
    if (model.name != lobes_[l].term.model.name)
      throw InputError("'" + spec + "' is not a " + lobes_[l].term.model.name + " where the fitted model is");
    const ModelInfo& info = find_model(model.name);
    for (const std::string& key : given_parameters(model))
      if (param_info(info, key).type != ParamType::choice)
        out.emplace_back(lobes_.size() > 1 ? lobes_[l].label + "." + key : key, model.values.at(key));
    const double relative_weight = canonical.terms[l].weight / canonical.terms.front().weight;
    if (l > 0) out.emplace_back(lobes_[l].label + ".weight", relative_weight);
  }
  return out;
}

}  // namespace ganzfeld::fit
