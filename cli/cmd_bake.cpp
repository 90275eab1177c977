// ganzfeld bake: one law of one model into an OpenEXR table (tables/, docs/lut-format.md), every
// table a scene needs into a cache directory (scene/plan.h, tables/cache.h), or one shard of a
// material library's tables into one (cli/library.h, docs/scale-out.md). A table whose file
// already carries exactly the requested key (spec, law, axes, tolerance, encoding, format
// version) is reused, not re-baked, unless --force.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "util/atomic_file.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/library.h"
#include "util/error.h"
#include "models/registry.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "tables/cache.h"
#include "tables/exr_io.h"
#include "tables/preset.h"
#include "util/progress.h"
#include "util/timing.h"
#include "scene/plan.h"
#include "scene/scene.h"

namespace ganzfeld::cli {

namespace {


// Defaults of a scene bake (scene::TableOptions, shared by every command that takes a scene): a
// scene's tables bake in about a second (the example scene's six tables: 1.6 s on 2 cores).
// Interpolation between nodes dominates the error: for g of specular:alpha=8 it is ~5.6e-3 at
// 25x25x13 (docs/lut-format.md, "Sampling"), somewhat less here; sharper lobes need --res-g raised.
constexpr double kModelTol = 1e-9;

struct BakeArgs {
  // one table
  std::string model, law, res, output, mapping, frame, interpolation, filter;
  // a preset table over a roughness axis (tables/preset.h)
  std::string preset, dfg_layout, axis, grid;
  std::optional<unsigned long long> checks;
  // a scene's tables, or a library's (one shard of them)
  std::string scene, library, out_dir;
  std::optional<std::string> shard;  ///< --shard K/N (absent: 0/1)
  // both: --tol, --encoding, --max-evals (and, for scenes, --res-g, --res-h)
  TableOptionArgs table;
  bool quiet = false, json = false, force = false;
  std::vector<std::string> argv;  ///< the command line, stamped into single tables
};

/// Refuses a --model spec that sets what a preset's axis and channels set (alpha, roughness,
/// alpha_x, alpha_y, f0): the table is over every alpha and fixes f0 per channel.
void refuse_preset_parameters(const std::string& spec) {
  for (const SpecTerm& term : parse_spec(spec).terms)
    for (const char* set : {"alpha", "roughness", "alpha_x", "alpha_y", "f0"})
      if (term.model.values.count(set))
        throw InputError("--preset: the model spec '" + spec + "' sets " + set +
                         ", which the table's axis and channels set; give the model as ggx or ggx:g2=...");
}

tables::PresetOptions preset_options(const BakeArgs& args) {
  tables::PresetOptions options;
  options.preset = tables::parse_preset(args.preset);
  if (!args.dfg_layout.empty()) {
    if (options.preset != tables::Preset::dfg) throw InputError("--dfg-layout is for --preset dfg");
    options.layout = tables::parse_dfg_layout(args.dfg_layout);
  }
  if (!args.axis.empty()) options.axis = args.axis;
  if (options.axis != tables::kAxisRoughness && options.axis != tables::kAxisAlpha)
    throw InputError("--axis '" + args.axis + "' is not allowed; allowed: roughness (alpha = R^2), alpha");
  if (!args.grid.empty()) options.grid = tables::parse_grid(args.grid);
  if (!args.res.empty()) options.resolution = tables::parse_preset_resolution(args.res);
  if (args.table.tol) validate_tolerance(*args.table.tol);
  options.tolerance = args.table.tol.value_or(tables::kPresetTolerance);
  if (!args.table.encoding.empty()) options.encoding = tables::parse_encoding(args.table.encoding);
  if (args.table.max_evaluations) {
    check_max_evaluations(*args.table.max_evaluations);
    options.max_evaluations = *args.table.max_evaluations;
  }
  return options;
}

/// bake --preset dfg|kulla-conty --model ggx -o FILE.exr: a format version 3 table.
int bake_preset_table(const BakeArgs& args) {
  for (const auto& [flag, set] : {std::pair{"--law", !args.law.empty()}, {"--mapping", !args.mapping.empty()},
                                  {"--frame", !args.frame.empty()}, {"--interpolation", !args.interpolation.empty()},
                                  {"--checks", args.checks.has_value()}, {"--max-error", args.table.max_error.has_value()}})
    if (set) throw InputError(std::string(flag) + " cannot be combined with --preset, which fixes it");
  if (args.output.empty()) throw InputError("bake --preset needs -o FILE.exr");
  tables::PresetOptions options = preset_options(args);
  refuse_preset_parameters(args.model);
  const ModelPtr model = parse_model(args.model);
  const std::string family = tables::preset_family(*model, options);
  check_writable(args.output);
  options.progress = util::progress_bar("baking preset " + args.preset + " of " + family, args.quiet);
  const util::Stopwatch watch;
  tables::ParamTable table = tables::bake_preset(*model, options);
  const double seconds = watch.seconds();
  table.command = shell_line(args.argv);
  tables::write_param_table(table, args.output);
  std::string channels;
  long long unconverged = 0;
  for (const tables::Channel& ch : table.channels) {
    channels += (channels.empty() ? "" : ", ") + ch.name;
    unconverged += ch.unconverged;
  }
  std::string lookup;  // per channel: the validated lookup error, the headline
  for (const tables::Channel& ch : table.channels) {
    char number[32];
    std::snprintf(number, sizeof number, "%.3g", ch.lookup_error);
    lookup += (lookup.empty() ? "" : ", ") + ch.name + " " + number;
  }
  std::printf("baked preset %s (%s) of %s, %dx%d %s-centred samples over (%s, cos_theta_i), channels %s, in %.2f s: "
              "lookup error %s (bilinear, validated at %lld points with alpha >= %s, cos_theta_i >= %s; per-texel "
              "error %.3g), %lld unconverged -> %s\n",
              table.preset.c_str(), table.layout.c_str(), table.model.c_str(), table.axes[0].count,
              table.axes[1].count, to_string(table.grid), table.axes[0].name.c_str(), channels.c_str(), seconds,
              lookup.c_str(), table.lookup_checks, format_number(tables::kMinValidatedAlpha).c_str(),
              format_number(tables::kMinValidatedMu).c_str(), table.node_error, unconverged, args.output.c_str());
  if (unconverged > 0)
    std::cerr << "ganzfeld: warning: " << unconverged << " texels missed tolerance " << format_number(table.tolerance)
              << "; their achieved error is stored\n";
  return 0;
}

int bake_one(const BakeArgs& args) {
  if (!args.preset.empty()) return bake_preset_table(args);
  for (const auto& [flag, set] : {std::pair{"--dfg-layout", !args.dfg_layout.empty()}, {"--axis", !args.axis.empty()},
                                  {"--grid", !args.grid.empty()}})
    if (set) throw InputError(std::string(flag) + " is for --preset bakes");
  // Everything is checked before the (possibly long) bake.
  if (args.law.empty()) throw InputError("bake --model needs --law g|h|a");
  const bool to_error = args.table.max_error.has_value();
  if (args.res.empty() && !to_error) throw InputError("bake --model needs --res N[xN[xN]] or --max-error E");
  if (!args.res.empty() && to_error)
    throw InputError("--res and --max-error are mutually exclusive: --max-error chooses the resolution itself");
  if (to_error)
    for (const auto& [flag, set] : {std::pair{"--mapping", !args.mapping.empty()}, {"--frame", !args.frame.empty()},
                                    {"--interpolation", !args.interpolation.empty()}, {"--checks", args.checks.has_value()},
                                    {"--filter", !args.filter.empty()}})
      if (set) throw InputError(std::string(flag) + " cannot be combined with --max-error, which chooses it itself");
  if (args.output.empty()) throw InputError("bake --model needs -o FILE.exr");
  const Law law = tables::parse_tabulated_law("--law", args.law);
  const ModelPtr model = parse_model(args.model);
  scene::TableOptions defaults;
  defaults.tolerance = kModelTol;
  const scene::TableOptions table_options = args.table.options(defaults);
  tables::BakeOptions options = table_options.bake_options(law);
  if (!to_error) options.resolution = tables::parse_resolution(args.res, law);
  else tables::check_error_target(options.target_error, options.max_bytes, law, options.encoding);
  if (!args.mapping.empty()) options.mappings = tables::parse_mappings(args.mapping, law);
  if (!args.interpolation.empty()) options.interpolation = tables::parse_interpolation(args.interpolation);
  const tables::Frame frame = args.frame.empty() ? tables::Frame::cosines : tables::parse_frame(args.frame);
  if (frame != tables::Frame::cosines) {
    if (law != Law::g)
      throw InputError(std::string("--frame ") + to_string(frame) + " is for law g; h and a tables use the cosines frame");
    options.lobe = tables::lobe_frame_of(*model);
    if (!options.lobe)
      throw InputError(std::string("--frame ") + to_string(frame) + ": model '" + model->spec() +
                       "' hints no lobe at the mirror direction or at j to follow; use --frame cosines");
    options.warped = frame == tables::Frame::warped;
  }
  if (!args.filter.empty()) {
    options.filter = tables::parse_filter(args.filter);
    if (options.filter == tables::Filter::hardware && options.interpolation != tables::Interpolation::linear)
      throw InputError("--filter hardware is validated for --interpolation linear only");
  }
  if (args.checks) options.random_checks = *args.checks;
  tables::table_key(*model, law, options);  // refuses bad axes now
  check_writable(args.output);
  attach_progress(options, args.quiet, law, model->spec());

  const tables::CacheResult r = tables::bake_or_reuse(args.output, *model, law, options, shell_line(args.argv), args.force);
  const tables::Table& table = r.table;
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"tables", {shapes::table_json(r.path, r.table, r.status, r.seconds)}}}.dump(2) << "\n";
  } else if (r.status == tables::CacheStatus::reused) {
    std::cerr << "ganzfeld: reused " << args.output << ": it already holds " << to_string(law) << " of "
              << table.model << " with the same axes, tolerance and encoding (--force re-bakes)\n";
  } else {
    std::string nodes;
    for (const tables::Axis& a : table.axes) nodes += (nodes.empty() ? "" : "x") + std::to_string(a.count);
    if (table.target_error > 0.0)
      std::printf("target lookup error %s within %llu value bytes%s: met\n", format_number(table.target_error).c_str(),
                  static_cast<unsigned long long>(table.target_bytes),
                  table.target_fetches ? (" and " + std::to_string(table.target_fetches) + " fetches").c_str() : "");
    std::printf("baked %s of %s, %s nodes (%s frame, %s, %s filter: %d fetches per lookup, %zu entries, %s, %llu value "
                "bytes) in %.2f s: lookup error %.3g (validated at %lld points%s; node error %.3g), %lld unconverged -> %s\n",
                to_string(law), table.model.c_str(), nodes.c_str(), to_string(table.frame),
                to_string(table.interpolation), to_string(table.filter), tables::fetches(table), table.entries(),
                to_string(table.encoding), static_cast<unsigned long long>(tables::value_bytes(table)), r.seconds,
                table.lookup_error, table.interpolation_checks,
                table.min_cos_j > 0.0 ? (" with j·n >= " + format_number(table.min_cos_j)).c_str() : "",
                table.node_error, table.unconverged, args.output.c_str());
  }
  warn_unconverged(r.table, r.status);
  return 0;
}

/// The node counts of a table's axes (a --max-error bake chooses them).
std::vector<int> axis_counts(const tables::Table& table) {
  std::vector<int> counts;
  for (const tables::Axis& a : table.axes) counts.push_back(a.count);
  return counts;
}

/// "baked g of SPEC, 32x32x16 nodes: lookup error ... -> PATH"
void print_table_line(const scene::PlannedTable& t) {
  std::printf("%s %s of %s, %s nodes: lookup error %.3g (validated; node error %.3g) -> %s\n",
              tables::to_string(t.status), to_string(t.request.law), t.request.spec.c_str(),
              tables::resolution_text(axis_counts(*t.table)).c_str(), t.table->lookup_error, t.table->node_error,
              t.path.c_str());
}

/// How many of `plan`'s tables were baked (the others were reused).
std::size_t baked_count(const scene::ShadingPlan& plan) {
  return static_cast<std::size_t>(std::count_if(plan.tables.begin(), plan.tables.end(), [](const scene::PlannedTable& t) {
    return t.status == tables::CacheStatus::baked;
  }));
}

int bake_scene(const BakeArgs& args) {
  if (args.out_dir.empty()) throw InputError("bake --scene needs --out DIR (the table cache directory)");
  const scene::TableOptions options = args.table.options(scene::TableOptions::scene_defaults());
  const Scene scene = load_scene(args.scene);
  const std::string dir = prepare_directory("--out", args.out_dir);
  const scene::ShadingPlan plan = scene::plan_shading(scene, options, table_store(dir, args.quiet, args.force));
  if (!args.json)
    for (const scene::PlannedTable& t : plan.tables) print_table_line(t);
  warn_unconverged(plan);
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"tables", tables_json(plan)}}.dump(2) << "\n";
  } else if (plan.tables.empty()) {
    std::printf("scene %s needs no tables (only collimated light, or Lambert lobes only)\n", args.scene.c_str());
  } else {
    const std::size_t baked = baked_count(plan);
    std::printf("%zu tables in %s: %zu baked, %zu reused\n", plan.tables.size(), dir.c_str(), baked,
                plan.tables.size() - baked);
  }
  return 0;
}

/// One shard of a library's tables into the cache --out (docs/scale-out.md): the library and the
/// shard are checked before the directory is created or anything is baked.
int bake_library(const BakeArgs& args) {
  if (args.out_dir.empty()) throw InputError("bake --library needs --out DIR (the table cache directory)");
  const Shard shard = args.shard ? parse_shard(*args.shard) : Shard{};
  const std::vector<scene::TableRequest> all = load_library(args.library);
  const std::vector<scene::TableRequest> mine = shard_of(all, shard);
  const std::string dir = prepare_directory("--out", args.out_dir);
  const scene::TableStore store = table_store(dir, args.quiet, args.force);
  scene::ShadingPlan plan;  // only its tables: the JSON and warnings of a scene bake
  for (const scene::TableRequest& request : mine) {
    plan.tables.push_back(scene::obtain_table(request, store));
    if (!args.json) print_table_line(plan.tables.back());
  }
  warn_unconverged(plan);
  const std::string name = std::to_string(shard.index) + "/" + std::to_string(shard.count);
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"shard", name}, {"library_tables", all.size()}, {"tables", tables_json(plan)}}.dump(2)
              << "\n";
  } else {
    const std::size_t baked = baked_count(plan);
    std::printf("shard %s: %zu of the library's %zu tables in %s: %zu baked, %zu reused\n", name.c_str(),
                plan.tables.size(), all.size(), dir.c_str(), baked, plan.tables.size() - baked);
  }
  return 0;
}

enum class BakeMode { model, scene, library };

/// The flags only some modes take; --tol, --encoding, --max-evals, --max-error, --max-bytes are
/// for --model and --scene (a library states them per accuracy).
struct ModeFlag {
  const char* flag;
  bool model, scene, library;
};
constexpr ModeFlag kModeFlags[] = {
    {"--law", true, false, false},   {"--res", true, false, false},       {"--mapping", true, false, false},
    {"--output", true, false, false}, {"--frame", true, false, false},    {"--interpolation", true, false, false},
    {"--checks", true, false, false}, {"--out", false, true, true},       {"--res-g", false, true, false},
    {"--res-h", false, true, false},  {"--shard", false, false, true},    {"--tol", true, true, false},
    {"--encoding", true, true, false}, {"--max-evals", true, true, false}, {"--max-error", true, true, false},
    {"--max-bytes", true, true, false}, {"--fetches", true, true, false}, {"--preset", true, false, false},
    {"--dfg-layout", true, false, false},
    {"--axis", true, false, false},   {"--grid", true, false, false}};

/// Which of --model, --scene, --library was given (exactly one), with no flag of another mode.
BakeMode bake_mode(const CLI::App& cmd) {
  const bool model = cmd.count("--model") > 0, scene = cmd.count("--scene") > 0, library = cmd.count("--library") > 0;
  if (model + scene + library > 1)
    throw InputError("--model, --scene and --library are mutually exclusive; bake one table (--model), a scene's "
                     "(--scene) or a library's (--library)");
  if (!model && !scene && !library)
    throw InputError("bake needs --model SPEC (one table, with --law, --res, -o), --scene SCENE.json --out DIR or "
                     "--library LIB.json --out DIR [--shard K/N]");
  const BakeMode mode = model ? BakeMode::model : scene ? BakeMode::scene : BakeMode::library;
  const char* name = model ? "--model" : scene ? "--scene" : "--library";
  for (const ModeFlag& f : kModeFlags) {
    const bool allowed = mode == BakeMode::model ? f.model : mode == BakeMode::scene ? f.scene : f.library;
    if (!allowed && cmd.count(f.flag) > 0) {
      const char* hint = mode == BakeMode::model     ? "with --model use --law, --res, -o FILE.exr"
                         : mode == BakeMode::scene ? "with --scene use --out DIR, --res-g, --res-h"
                                                   : "with --library use --out DIR, --shard K/N; accuracies go in the library";
      throw InputError(std::string(f.flag) + " is not for " + name + " bakes; " + hint);
    }
  }
  return mode;
}

}  // namespace

void add_bake_command(CLI::App& app, Action& action, int argc, const char* const* argv) {
  auto* cmd = app.add_subcommand(
      "bake",
      "tabulate a law (g, h, a) of a model into an OpenEXR table with per-entry error, or every table a scene "
      "needs into a cache directory; a file that already holds exactly the requested table is reused");
  auto args = std::make_shared<BakeArgs>();
  args->argv.assign(argv, argv + argc);
  cmd->add_option("--model", args->model, "one table: model spec, e.g. specular:alpha=8 (see `ganzfeld models`)");
  cmd->add_option("--law", args->law, "one table: g (vignetting, 3-D), h (darkening, 1-D) or a (albedo, 1-D)");
  cmd->add_option("--res", args->res,
                  "one table: nodes per axis, N or NIxNJxNPHI for g (axes cos_theta_i, cos_theta_j, phi); each >= 2");
  cmd->add_option("--mapping", args->mapping,
                  "one table: axis mappings, M or MxMxM for g (M = linear, sqrt, cos; default: the law's defaults)");
  cmd->add_option("--frame", args->frame,
                  "one table: g axes, cosines (i·n, j·n, phi; default), lobe (theta_j, psi, beta about the lobe's "
                  "peak) or warped (theta_j, the sky edge's warped offset from the lobe, beta; docs/lut-format.md)");
  cmd->add_option("--filter", args->filter,
                  "one table: the lookup its bound covers, texel-fetch (default) or hardware (one GPU-filtered fetch, "
                  "8-bit weights; linear interpolation only)");
  cmd->add_option("--interpolation", args->interpolation, "one table: lookup, linear (default) or catmull-rom");
  cmd->add_option("--checks", args->checks,
                  "one table: seeded random validation points (besides the cell centres) against direct cubature");
  cmd->add_option("--preset", args->preset,
                  "one table over a roughness axis, as engines read it: dfg (split-sum DFG) or kulla-conty (E, E_avg); "
                  "--model ggx[:g2=...]; docs/lut-format.md, version 3");
  cmd->add_option("--dfg-layout", args->dfg_layout,
                  "--preset dfg channels: filament (default: dfg_fc, dfg_e, charlie) or ue4 (scale, bias)");
  cmd->add_option("--axis", args->axis, "--preset: the parameter axis, roughness (default; alpha = R^2) or alpha");
  cmd->add_option("--grid", args->grid,
                  "--preset: texel (default; sample k at (k + 0.5)/N, what a GPU lookup reads) or node (k/(N - 1))");
  cmd->add_option("-o,--output", args->output, "one table: the table to write, FILE.exr (written atomically)");
  cmd->add_option("--scene", args->scene, "a scene's tables: the scene file, SCENE.json (e.g. examples/default.json)");
  cmd->add_option("--library", args->library,
                  "a library's tables: LIB.json, groups of model specs x laws x accuracies (docs/scale-out.md)");
  cmd->add_option("--shard", args->shard,
                  "a library's tables: bake only shard K of N (K/N, 0 <= K < N; default 0/1, all); the N shards "
                  "are disjoint and together are the whole library");
  cmd->add_option("--out", args->out_dir,
                  "a scene's or a library's tables: the cache directory (created if its parent exists); file "
                  "names are SPEC.LAW.HASH.exr");
  args->table.add_to(*cmd, scene::TableOptions::scene_defaults());  // --res-g, --res-h (scenes), --tol, --encoding, ...
  cmd->add_flag("--force", args->force, "bake even when the file already holds exactly this table");
  cmd->add_flag("--quiet", args->quiet, "no progress bar (it is shown only when stderr is a terminal)");
  add_json_flag(*cmd, args->json, "{\"tables\": [{path, model, law, status}, ...]}");
  cmd->callback([&action, args, cmd] {
    action = [args, cmd] {
      const BakeMode mode = bake_mode(*cmd);
      return mode == BakeMode::model ? bake_one(*args) : mode == BakeMode::scene ? bake_scene(*args) : bake_library(*args);
    };
  });
}

}  // namespace ganzfeld::cli
