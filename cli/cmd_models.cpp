#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "laws/registry.h"
#include "util/atomic_file.h"

namespace ganzfeld::cli {

namespace {

const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::real: return "real";
    case ParamType::integer: return "integer";
    case ParamType::choice: return "choice";
  }
  return "?";
}

/// A default as a spec would write it: the name of a choice, else the number.
std::string default_text(const ParamInfo& p) {
  if (p.type == ParamType::choice) return p.choices.at(static_cast<std::size_t>(p.default_value));
  return format_number(p.default_value);
}

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

/// A parameter's default as the JSON holds it: a choice's name, a number, or "optional".
std::string default_cell(const nlohmann::ordered_json& p) {
  if (p.contains("optional")) return "optional";
  return p["default"].is_string() ? p["default"].get<std::string>() : format_number(p["default"].get<double>());
}

/// docs/model-parameters.md: every model's parameter table, generated from the registry (the
/// same data as --json), so that docs/models.md never copies a range or a default by hand.
std::string models_markdown(const nlohmann::ordered_json& doc) {
  std::string md =
      "# Model parameters\n\nGenerated from the model registry by `ganzfeld models --markdown "
      "docs/model-parameters.md`; a test keeps it current. Formulas, sources and measured traits: "
      "[models.md](models.md).\n\nMixtures: " + doc["mixtures"].get<std::string>() + ".\n";
  for (const auto& m : doc["models"]) {
    md += "\n## " + m["name"].get<std::string>() + "\n\n" + markdown_cell(m["summary"].get<std::string>()) + " (" +
          markdown_cell(m["source"].get<std::string>()) + "). Example: `" + m["example"].get<std::string>() + "`. " +
          (m["isotropic"].get<bool>() ? "Isotropic" : "Anisotropic") + ", " +
          (m["reciprocal"].get<bool>() ? "reciprocal" : "not reciprocal") + ", energy: " +
          m["energy_class"].get<std::string>() + ".\n";
    if (m["parameters"].empty()) continue;
    md += "\n| param | allowed | default | meaning |\n|---|---|---|---|\n";
    for (const auto& p : m["parameters"]) {
      const bool path = p["type"] == "path";
      md += "| " + p["name"].get<std::string>() + " | " +
            markdown_cell(path ? std::string("a file path") : p["allowed"].get<std::string>()) + " | " +
            (path ? std::string(p["required"].get<bool>() ? "required" : "optional") : default_cell(p)) + " | " +
            markdown_cell(p["meaning"].get<std::string>()) + " |\n";
    }
  }
  return md;
}

}  // namespace

void add_models_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("models", "list every model: parameters, traits, closed forms");
  auto json = std::make_shared<bool>(false);
  auto markdown = std::make_shared<std::string>();
  cmd->add_flag("--json", *json, "print one JSON document");
  cmd->add_option("--markdown", *markdown, "write every model's parameter table as markdown (docs/model-parameters.md)");
  cmd->callback([&action, json, markdown] {
    action = [json, markdown] {
      if (!markdown->empty()) check_writable(*markdown);
      nlohmann::ordered_json doc;
      doc["models"] = nlohmann::ordered_json::array();
      for (const auto& m : model_catalogue()) {
        nlohmann::ordered_json params = nlohmann::ordered_json::array();
        std::string example = m.name;
        if (m.make_with_file) {  // file=PATH comes first; required unless the model has a default
          params.push_back({{"name", "file"},
                            {"type", "path"},
                            {"required", !m.file_optional},
                            {"meaning", m.file_meaning + " (no ',', '+' or '*' in the path)"}});
          if (!m.file_optional) example += ":file=DATA";
        }
        for (const auto& p : m.parameters) {
          nlohmann::ordered_json param{{"name", p.name},
                                       {"type", type_name(p.type)},
                                       {"min", p.min},
                                       {"max", p.max},
                                       {"default", p.default_value},
                                       {"meaning", p.meaning}};
          if (p.type == ParamType::choice) {
            param["choices"] = p.choices;
            param["default"] = default_text(p);  // the name, as a spec gives it
          }
          if (p.min_exclusive) param["min_exclusive"] = true;
          if (p.optional) param["optional"] = true;
          param["allowed"] = allowed_values(p);
          params.push_back(param);
          if (!p.optional) example += (example == m.name ? ":" : ",") + p.name + "=" + default_text(p);
        }
        doc["models"].push_back({{"name", m.name},
                                 {"summary", m.summary},
                                 {"source", m.source},
                                 {"example", example},
                                 {"parameters", params},
                                 {"isotropic", m.traits.isotropic},
                                 {"reciprocal", m.traits.reciprocal},
                                 {"energy_class", to_string(m.traits.energy)},
                                 {"closed_forms", m.closed_forms}});
      }
      doc["mixtures"] = "W1*SPEC1 + W2*SPEC2 + ... (partitive mixture; weights > 0 are normalized)";
      if (!markdown->empty()) write_text_atomically(*markdown, models_markdown(doc), "markdown");
      if (*json) {
        std::cout << doc.dump(2) << "\n";
        return 0;
      }
      if (!markdown->empty()) return 0;
      for (const auto& m : doc["models"]) {
        std::cout << m["name"].get<std::string>() << " — " << m["summary"].get<std::string>() << "\n"
                  << "    example: " << m["example"].get<std::string>() << "\n"
                  << "    traits: " << (m["isotropic"].get<bool>() ? "isotropic" : "anisotropic") << ", "
                  << (m["reciprocal"].get<bool>() ? "reciprocal" : "not reciprocal") << ", "
                  << m["energy_class"].get<std::string>() << "\n";
        for (const auto& p : m["parameters"]) {
          if (p["type"] == "path") {
            std::cout << "    " << p["name"].get<std::string>() << " (path, "
                      << (p["required"].get<bool>() ? "required" : "optional") << "): " << p["meaning"].get<std::string>()
                      << "\n";
            continue;
          }
          std::cout << "    " << p["name"].get<std::string>() << " (" << p["allowed"].get<std::string>()
                    << (p.contains("optional") ? std::string(", optional") : ", default " + default_cell(p)) << "): "
                    << p["meaning"].get<std::string>() << "\n";
        }
      }
      std::cout << "mixtures: " << doc["mixtures"].get<std::string>() << "\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
