#include "models/registry.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "models/kp_lobes.h"
#include "util/error.h"

namespace ganzfeld {

namespace {
const char* kKp = "Koenderink & Pont 2019, \"Material Properties and Extended Sources\"";

std::vector<ModelInfo> build_catalogue() {
  std::vector<ModelInfo> c;
  c.push_back({"lambert",
               "Lambertian bulk scattering, f = 1/pi",
               std::string(kKp) + ", Extended Sources",
               {},
               {true, true, EnergyClass::conserving},
               {"lambert.g", "lambert.h", "lambert.a", "lambert.r"},
               [](const ParamValues&) { return std::make_shared<Lambert>(); }});
  c.push_back({"minnaert",
               "Minnaert diffuse lobe with edge darkening, f = C_d ((i.n)(j.n))^xi",
               std::string(kKp) + ", Bulk Scattering",
               {{"xi", ParamType::real, 0.0, 1000.0, 1.0, "edge-darkening exponent (0 = Lambert)"}},
               {true, true, EnergyClass::plausible},
               {"minnaert.g.xi1", "minnaert.g.hyp2f1", "minnaert.g.betainc", "minnaert.h", "minnaert.a", "minnaert.r",
                "minnaert.norm"},
               [](const ParamValues& p) { return std::make_shared<Minnaert>(p.at("xi")); }});
  c.push_back({"specular",
               "specular lobe about the mirror direction, f = C_s ((1 + k.j)/2)^alpha",
               std::string(kKp) + ", Specular reflection",
               {{"alpha", ParamType::real, 1.0, 10000.0, 8.0, "lobe sharpness (paper: integers >= 1)"}},
               {true, true, EnergyClass::plausible},
               {"specular.a.alpha1", "specular.a.alpha8", "specular.norm"},
               [](const ParamValues& p) { return std::make_shared<Specular>(p.at("alpha")); }});
  c.push_back({"backscatter",
               "backscatter lobe about the source direction, f = C_b ((1 + i.j)/2)^alpha",
               std::string(kKp) + ", Backscattering",
               {{"alpha", ParamType::real, 1.0, 10000.0, 1.0, "lobe sharpness"}},
               {true, true, EnergyClass::plausible},
               {"backscatter.g.alpha1", "backscatter.h.alpha1", "backscatter.norm"},
               [](const ParamValues& p) { return std::make_shared<Backscatter>(p.at("alpha")); }});
  c.push_back(
      {"perfect-backscatter",
       "perfect backscatterer (uniform full moon), f = C_pb (1 + i.j)^alpha / ((i + j).n)",
       std::string(kKp) + ", Backscattering",
       {{"alpha", ParamType::integer, 2.0, 10000.0, 2.0, "lobe sharpness (integer >= 2)"}},
       {true, true, EnergyClass::plausible},
       {"perfect-backscatter.norm", "perfect-backscatter.retro"},
       [](const ParamValues& p) { return std::make_shared<PerfectBackscatter>(static_cast<int>(p.at("alpha"))); }});
  c.push_back({"asperity",
               "asperity (velvet) lobe along the surface, f = C_a (1 - (i.n)(j.n))^alpha",
               std::string(kKp) + ", Asperity Scattering",
               {{"alpha", ParamType::real, 1.0, 10000.0, 1.0, "lobe sharpness"}},
               {true, true, EnergyClass::plausible},
               {"asperity.g.alpha1", "asperity.h.alpha1", "asperity.norm"},
               [](const ParamValues& p) { return std::make_shared<Asperity>(p.at("alpha")); }});
  register_hvd_models(c);
  register_classic_models(c);
  register_he_torrance_models(c);
  register_kajiya_models(c);
  register_blinn_dusty_models(c);
  register_beard_maxwell_models(c);
  register_poulin_fournier_models(c);
  register_ggx_models(c);
  register_charlie_models(c);
  register_ashikhmin_shirley_models(c);
  register_schlick_models(c);
  register_measured_models(c);
  return c;
}
}  // namespace

const std::vector<ModelInfo>& model_catalogue() {
  static const std::vector<ModelInfo> catalogue = build_catalogue();
  return catalogue;
}

const ModelInfo& find_model(const std::string& name) {
  std::string known;
  for (const auto& m : model_catalogue()) {
    if (m.name == name) return m;
    known += (known.empty() ? "" : ", ") + m.name;
  }
  throw InputError("unknown model '" + name + "'; known models: " + known);
}

std::string format_number(double value) {
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, result.ptr);
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

std::string value_text(const ParamInfo& param, double value) {
  if (param.type == ParamType::choice) return param.choices.at(static_cast<std::size_t>(value));
  return format_number(value);
}

std::string allowed_values(const ParamInfo& param) {
  if (param.type == ParamType::choice) {
    std::string names;
    for (const auto& c : param.choices) names += (names.empty() ? "" : ", ") + c;
    return "one of " + names;
  }
  return std::string(param.type == ParamType::integer ? "an integer" : "a real number") + " in " +
         (param.min_exclusive ? "(" : "[") + format_number(param.min) + ", " + format_number(param.max) + "]";
}

void validate_param(const ModelInfo& model, const ParamInfo& param, double value) {
  const std::string allowed = allowed_values(param);
  const std::string where = model.name + ": " + param.name + "=" + format_number(value);
  if (!std::isfinite(value)) throw InputError(where + " is not finite; allowed: " + allowed);
  if (value < param.min || value > param.max || (param.min_exclusive && value == param.min))
    throw InputError(where + " is out of range; allowed: " + allowed);
  if (param.type != ParamType::real && value != std::floor(value))
    throw InputError(where + " is not an integer; allowed: " + allowed);
}

double parse_choice(const ModelInfo& model, const ParamInfo& param, const std::string& text) {
  for (std::size_t k = 0; k < param.choices.size(); ++k)
    if (param.choices[k] == text) return static_cast<double>(k);
  throw InputError(model.name + ": " + param.name + "='" + text +
                   "' is not allowed; allowed: " + allowed_values(param));
}

}  // namespace ganzfeld
