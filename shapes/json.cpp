#include "shapes/json.h"

#include <array>

#include "models/registry.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "util/names.h"

namespace ganzfeld::shapes {

namespace {

const char* type_name(ParamType t) {
  constexpr std::array kNames{util::EnumName<ParamType>{ParamType::real, "real"},
                              util::EnumName<ParamType>{ParamType::integer, "integer"},
                              util::EnumName<ParamType>{ParamType::choice, "choice"}};
  return util::name_of(kNames, t);
}

nlohmann::ordered_json model_json(const ModelInfo& m) {
  nlohmann::ordered_json params = nlohmann::ordered_json::array();
  ModelSpec example{m.name};  // every parameter at its default; a required data file as DATA
  if (m.make_with_file) {     // file=PATH comes first; required unless the model has a default
    params.push_back({{"name", "file"},
                      {"type", "path"},
                      {"required", !m.file_optional},
                      {"meaning", m.file_meaning + " (no ',', '+' or '*' in the path)"}});
    if (!m.file_optional) example.file = "DATA";
  }
  for (const auto& p : m.parameters) {
    nlohmann::ordered_json param{{"name", p.name}, {"type", type_name(p.type)},  {"min", p.min},
                                 {"max", p.max},   {"default", p.default_value}, {"meaning", p.meaning}};
    if (p.type == ParamType::choice) {
      param["choices"] = p.choices;
      param["default"] = value_text(p, p.default_value);  // the name, as a spec gives it
    }
    if (p.min_exclusive) param["min_exclusive"] = true;
    if (p.optional) param["optional"] = true;
    param["allowed"] = allowed_values(p);
    params.push_back(param);
    if (!p.optional) example.values[p.name] = p.default_value;
  }
  return {{"name", m.name},
          {"summary", m.summary},
          {"source", m.source},
          {"example", spec_text(example)},
          {"parameters", params},
          {"isotropic", m.traits.isotropic},
          {"reciprocal", m.traits.reciprocal},
          {"energy_class", to_string(m.traits.energy)},
          {"closed_forms", m.closed_forms}};
}

}  // namespace

nlohmann::ordered_json models_json() {
  nlohmann::ordered_json doc;
  doc["models"] = nlohmann::ordered_json::array();
  for (const auto& m : model_catalogue()) doc["models"].push_back(model_json(m));
  doc["mixtures"] = "W1*SPEC1 + W2*SPEC2 + ... (partitive mixture; weights > 0 are normalized)";
  return doc;
}

nlohmann::ordered_json spec_json(const Spec& spec, const std::string& canonical) {
  nlohmann::ordered_json terms = nlohmann::ordered_json::array();
  for (const SpecTerm& term : spec.terms) {
    nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
    for (const ParamInfo& p : find_model(term.model.name).parameters) {
      const auto given = term.model.values.find(p.name);
      if (given == term.model.values.end()) continue;
      if (p.type == ParamType::choice) parameters[p.name] = value_text(p, given->second);
      else parameters[p.name] = given->second;
    }
    nlohmann::ordered_json t{{"weight", term.weight}, {"model", term.model.name}, {"parameters", parameters}};
    if (!term.model.file.empty()) t["file"] = term.model.file;
    terms.push_back(t);
  }
  return {{"canonical", canonical}, {"terms", terms}};
}

nlohmann::ordered_json eval_json(const std::string& spec, Law law, const Estimate& e, double tolerance,
                                 const std::optional<Vec3>& i, const std::optional<Vec3>& j, double seconds) {
  nlohmann::ordered_json doc{{"model", spec},         {"law", to_string(law)},        {"value", e.value},
                             {"error", e.error},      {"evaluations", e.evaluations}, {"converged", e.converged},
                             {"tolerance", tolerance}};
  if (i) doc["i"] = {i->x, i->y, i->z};
  if (j) doc["j"] = {j->x, j->y, j->z};
  doc["seconds"] = seconds;
  return doc;
}

nlohmann::ordered_json table_json(const std::string& path, const tables::Table& table, tables::CacheStatus status,
                                  double seconds) {
  return {{"path", path.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(path)},
          {"model", table.model},
          {"law", to_string(table.law)},
          {"status", to_string(status)},
          {"entries", table.entries()},
          {"value_bytes", tables::value_bytes(table)},
          {"lookup_error", table.lookup_error},
          {"node_error", table.node_error},
          {"unconverged", table.unconverged},
          {"seconds", seconds}};
}

nlohmann::ordered_json info_json(const std::string& path, const tables::Table& table) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (const tables::Axis& a : table.axes) {
    nlohmann::ordered_json axis{
        {"name", a.name}, {"min", a.min}, {"max", a.max}, {"count", a.count}, {"mapping", to_string(a.mapping)}};
    if (a.has_width()) axis["width"] = a.width;
    axes.push_back(axis);
  }
  nlohmann::ordered_json doc{{"path", path},
                             {"format_version", table.format_version},
                             {"model", table.model},
                             {"model_content", table.model_content},
                             {"law", to_string(table.law)},
                             {"frame", to_string(table.frame)},
                             {"interpolation", to_string(table.interpolation)},
                             {"axes", axes},
                             {"entries", table.entries()},
                             {"value_bytes", tables::value_bytes(table)},
                             {"error", table.lookup_error},
                             {"validation_points", table.interpolation_checks},
                             {"node_error", table.node_error},
                             {"measured_lookup_error", table.interpolation_error},
                             {"tolerance", table.tolerance},
                             {"unconverged", table.unconverged},
                             {"encoding", to_string(table.encoding)},
                             {"command", table.command},
                             {"version", table.version}};
  if (table.frame != tables::Frame::cosines) doc["peak"] = to_string(table.peak);
  // Which lookup `error` is for (docs/lut-format.md, "Sampling"), what it costs, and where it holds.
  doc["filter"] = to_string(table.filter);
  doc["fetches"] = tables::fetches(table);
  doc["min_cos_theta_j"] = table.min_cos_j;
  if (table.frame == tables::Frame::warped) doc["warp"] = nlohmann::ordered_json::parse(tables::warp_text(table.warp));
  if (table.encoding == tables::Encoding::unorm16)  // value = offset + scale u / 65535
    doc["unorm16"] = {{"offset", table.unorm.offset}, {"scale", table.unorm.scale}};
  if (table.target_error > 0.0) {
    doc["target_error"] = table.target_error;
    doc["target_bytes"] = table.target_bytes;
    if (table.target_fetches > 0) doc["target_fetches"] = table.target_fetches;
  }
  return doc;
}

}  // namespace ganzfeld::shapes
