#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "laws/registry.h"

namespace ganzfeld::cli {

void add_models_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("models", "list every model: parameters, traits, closed forms");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "print one JSON document");
  cmd->callback([&action, json] {
    action = [json] {
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
          params.push_back({{"name", p.name},
                            {"type", p.type == ParamType::integer ? "integer" : "real"},
                            {"min", p.min},
                            {"max", p.max},
                            {"default", p.default_value},
                            {"meaning", p.meaning}});
          example += (example == m.name ? ":" : ",") + p.name + "=" + format_number(p.default_value);
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
      if (*json) {
        std::cout << doc.dump(2) << "\n";
        return 0;
      }
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
          std::cout << "    " << p["name"].get<std::string>() << " (" << p["type"].get<std::string>() << " in ["
                    << format_number(p["min"]) << ", " << format_number(p["max"]) << "], default "
                    << format_number(p["default"]) << "): " << p["meaning"].get<std::string>() << "\n";
        }
      }
      std::cout << "mixtures: " << doc["mixtures"].get<std::string>() << "\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
