// ganzfeld export-glsl: tables for real-time shaders (export/glsl.h, export/texture_file.h,
// docs/shaders.md).
//   export-glsl TABLE.exr -o LAW.glsl [--texture ktx2|header|none] [--model SPEC --law L]
//       the sampling function of one table, and its texture beside it (LAW.ktx2 or LAW.h);
//       --model/--law state what the shader expects: a table of another model or law is refused.
//   export-glsl --scene SCENE.json --out DIR [--cache DIR] [table options as bake scene] [--texture ...]
//       DIR/ganzfeld_scene.glsl (the reference shading of every material), one texture and one
//       sampling snippet per table the scene needs (named after its sampler uniform) and
//       DIR/manifest.json binding them.
// The shader is generated, and every refusal made, before the first file is written; each file is
// written atomically (a crash between files can leave some of a scene's files, never a partial one).
#include <filesystem>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "export/glsl.h"
#include "export/param_export.h"
#include "export/texture_file.h"
#include "models/registry.h"
#include "models/spec.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/exr_io.h"
#include "tables/param_table.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace ganzfeld::cli {

namespace {

struct ExportArgs {
  std::string table, output, scene, out_dir, texture, model, law;  ///< texture "": ktx2 (header for version 3)
  TableOptionArgs tables;  // with --scene: the same table options as `bake scene` and `render`
  CacheArgs cache;         // with --scene
  bool json = false, quiet = false;
};

std::optional<exporting::TextureFormat> texture_format(const std::string& text) {
  if (text == "none") return std::nullopt;
  if (text.empty()) return exporting::TextureFormat::ktx2;
  try {
    return exporting::parse_texture_format(text);
  } catch (const InputError&) { throw InputError("unknown --texture '" + text + "'; allowed: ktx2, header, none"); }
}

/// Writes a table's snippet to -o and says so: with --json `doc` and the texture's path ("texture",
/// null when none was written), else "wrote FILE.glsl [and TEXTURE]".
int write_snippet(const ExportArgs& args, const std::string& glsl, nlohmann::ordered_json doc,
                  const std::string& texture_path) {
  write_text_atomically(args.output, glsl, "shader");
  if (args.json) {
    doc["texture"] = texture_path.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(texture_path);
    std::cout << doc.dump(2) << "\n";
  } else if (!args.quiet) {
    std::cout << "wrote " << args.output << (texture_path.empty() ? "" : " and " + texture_path) << "\n";
  }
  return 0;
}

/// A parameter table (format version 3): its GLSL lookup and, by default, its C header.
int export_param_table(const ExportArgs& args) {
  if (!args.model.empty() || !args.law.empty())
    throw InputError("--model and --law are for law tables; '" + args.table + "' is a parameter table (version 3)");
  if (args.texture == "ktx2")
    throw InputError("--texture ktx2 is not available for parameter tables; allowed: header (the default), none");
  const tables::ParamTable table = tables::read_param_table(args.table);
  const std::string glsl = exporting::glsl_param_snippet(table), name = exporting::glsl_param_function_name(table);
  std::string header_path;
  if (args.texture != "none") {
    texture_format(args.texture);  // refuses anything but header here
    header_path = std::filesystem::path(args.output).replace_extension(".h").string();
    write_text_atomically(header_path, exporting::param_c_header(table, name), "texture");
  }
  return write_snippet(args, glsl,
                       {{"glsl", args.output},
                        {"function", name},
                        {"sampler", "sampler2D"},
                        {"model", table.model},
                        {"preset", table.preset}},
                       header_path);
}

int export_table(const ExportArgs& args) {
  if (args.output.empty()) throw InputError("export-glsl TABLE.exr needs -o FILE.glsl");
  if (std::filesystem::path(args.output).extension() != ".glsl")
    throw InputError("output '" + args.output + "' must end in .glsl");
  if (tables::format_version_of(args.table) == tables::kParamFormatVersion) return export_param_table(args);
  const auto format = texture_format(args.texture);
  const tables::Table table = tables::read_table(args.table);
  if (!args.model.empty() || !args.law.empty()) {
    if (args.model.empty() || args.law.empty())
      throw InputError("--model and --law go together (the table the shader expects)");
    const Law law = tables::parse_tabulated_law("--law", args.law);
    exporting::check_table_is(table, *parse_model(args.model), law);
  }
  const std::string glsl = exporting::glsl_table_snippet(table);
  std::string texture_path;
  if (format) {
    texture_path = std::filesystem::path(args.output).replace_extension(exporting::texture_extension(*format)).string();
    exporting::write_texture(table, *format, texture_path, exporting::glsl_function_name(table.model, table.law));
  }
  return write_snippet(args, glsl,
                       {{"glsl", args.output},
                        {"function", exporting::glsl_function_name(table.model, table.law)},
                        {"sampler", exporting::glsl_sampler_type(table.law)},
                        {"model", table.model},
                        {"law", to_string(table.law)}},
                       texture_path);
}

int export_scene(const ExportArgs& args) {
  if (args.out_dir.empty()) throw InputError("export-glsl --scene needs --out DIR");
  const auto format = texture_format(args.texture);
  const scene::TableOptions options = args.tables.options(scene::TableOptions::scene_defaults());
  const Scene scene = load_scene(args.scene);
  exporting::check_scene_exportable(scene);  // before any bake
  const scene::ShadingPlan plan = scene::plan_shading(scene, options, args.cache.store(args.quiet || args.json));
  warn_unconverged(plan);
  const std::string glsl = exporting::glsl_scene_shader(scene, plan, args.scene);  // refuses before any file is written

  const std::string dir = prepare_directory("--out", args.out_dir);
  nlohmann::ordered_json manifest{{"scene", args.scene}, {"glsl", "ganzfeld_scene.glsl"}};
  nlohmann::ordered_json textures = nlohmann::ordered_json::array();
  for (const scene::PlannedTable& planned : plan.tables) {
    const tables::Table* table = planned.table.get();
    const std::string sampler = exporting::glsl_sampler_name(planned.request.spec, planned.request.law);
    nlohmann::ordered_json entry{{"sampler", sampler},
                                 {"type", exporting::glsl_sampler_type(planned.request.law)},
                                 {"model", planned.request.spec},
                                 {"law", to_string(planned.request.law)},
                                 {"lookup_error", table->lookup_error},
                                 {"node_error", table->node_error},
                                 {"frame", to_string(table->frame)},
                                 {"filter", to_string(table->filter)},
                                 {"fetches", tables::fetches(*table)}};
    if (format) {
      const std::string file = sampler + exporting::texture_extension(*format);
      exporting::write_texture(*table, *format, (std::filesystem::path(dir) / file).string(), sampler);
      entry["file"] = file;
      // The table's own snippet beside its texture, for engines that bind tables one by one
      // (js/ganzfeld-three): what `export-glsl FILE.exr` writes for it.
      const std::string snippet = sampler + ".glsl";
      write_text_atomically((std::filesystem::path(dir) / snippet).string(), exporting::glsl_table_snippet(*table),
                            "shader");
      entry["glsl"] = snippet;
      entry["function"] = exporting::glsl_function_name(table->model, table->law);
    }
    textures.push_back(entry);
  }
  manifest["textures"] = textures;
  write_text_atomically((std::filesystem::path(dir) / "manifest.json").string(), manifest.dump(2) + "\n", "manifest");
  write_text_atomically((std::filesystem::path(dir) / "ganzfeld_scene.glsl").string(), glsl, "shader");
  if (args.json) {
    manifest["out"] = dir;
    manifest["tables"] = tables_json(plan);
    std::cout << manifest.dump(2) << "\n";
  } else if (!args.quiet) {
    std::cout << "wrote " << dir << "/ganzfeld_scene.glsl, manifest.json and " << textures.size() << " textures\n";
  }
  return 0;
}

}  // namespace

void add_export_glsl_command(CLI::App& app, Action& action) {
  auto* cmd =
      app.add_subcommand("export-glsl",
                         "GLSL (4.30 core, ES 3.00) that samples a table exactly as tables/ does, plus the table as "
                         "a texture; or everything a scene's shader needs (docs/shaders.md)");
  auto args = std::make_shared<ExportArgs>();
  cmd->add_option("TABLE", args->table, "a table written by `ganzfeld bake` (omit with --scene)");
  cmd->add_option("-o,--output", args->output, "the GLSL snippet, FILE.glsl; the texture goes beside it");
  cmd->add_option("--texture", args->texture,
                  "texture file: ktx2 (KTX 2.0, R32F or R16F, the default), header (C array) or none; parameter "
                  "tables (version 3): header (half floats, the default) or none");
  cmd->add_option("--model", args->model, "the model the shader expects: a table of another model is refused");
  cmd->add_option("--law", args->law, "the law the shader expects (g, h, a): a table of another law is refused");
  cmd->add_option("--scene", args->scene, "export the reference shader and every table of SCENE.json instead");
  cmd->add_option("--out", args->out_dir, "with --scene: the output directory (created if its parent exists)");
  args->cache.add_to(*cmd, "with --scene: ");
  args->tables.add_to(
      *cmd, scene::TableOptions::scene_defaults());  // with --scene: --res-g, --res-h, --tol, --encoding, --max-evals
  cmd->add_flag("--quiet", args->quiet, "no progress and no summary line");
  add_json_flag(*cmd, args->json);
  cmd->callback([&action, args] {
    action = [args] {
      if (args->scene.empty() == args->table.empty())
        throw InputError("export-glsl needs either TABLE.exr -o FILE.glsl or --scene SCENE.json --out DIR");
      return args->scene.empty() ? export_table(*args) : export_scene(*args);
    };
  });
}

}  // namespace ganzfeld::cli
