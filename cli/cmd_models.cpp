#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "shapes/json.h"
#include "util/atomic_file.h"

namespace ganzfeld::cli {

namespace {

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
      "[models.md](models.md).\n\nMixtures: " +
      doc["mixtures"].get<std::string>() + ".\n";
  for (const auto& m : doc["models"]) {
    md += "\n## " + m["name"].get<std::string>() + "\n\n" + markdown_cell(m["summary"].get<std::string>()) + " (" +
          markdown_cell(m["source"].get<std::string>()) + "). Example: `" + m["example"].get<std::string>() + "`. " +
          (m["isotropic"].get<bool>() ? "Isotropic" : "Anisotropic") + ", " +
          (m["reciprocal"].get<bool>() ? "reciprocal" : "not reciprocal") +
          ", energy: " + m["energy_class"].get<std::string>() + ".\n";
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
  add_json_flag(*cmd, *json);
  cmd->add_option("--markdown", *markdown,
                  "write every model's parameter table as markdown (docs/model-parameters.md)");
  cmd->callback([&action, json, markdown] {
    action = [json, markdown] {
      if (!markdown->empty()) check_writable(*markdown);
      const nlohmann::ordered_json doc = shapes::models_json();
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
                      << (p["required"].get<bool>() ? "required" : "optional")
                      << "): " << p["meaning"].get<std::string>() << "\n";
            continue;
          }
          std::cout << "    " << p["name"].get<std::string>() << " (" << p["allowed"].get<std::string>()
                    << (p.contains("optional") ? std::string(", optional") : ", default " + default_cell(p))
                    << "): " << p["meaning"].get<std::string>() << "\n";
        }
      }
      std::cout << "mixtures: " << doc["mixtures"].get<std::string>() << "\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
