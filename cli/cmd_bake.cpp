// ganzfeld bake: four jobs, one subcommand each, each with only its own flags: `bake model` (one
// law of one model into an OpenEXR table, on a fixed grid or to an error target: tables/bake.h,
// docs/lut-format.md), `bake preset` (a table over a roughness axis, tables/preset.h), `bake scene`
// (every table a scene needs into a cache directory, scene/plan.h, tables/cache.h) and `bake
// library` (one shard of a material library's tables, cli/library.h, docs/scale-out.md). The
// spellings `bake --model/--preset/--scene/--library` remain aliases (bake_alias). A table whose
// file already carries exactly the requested key (spec, law, axes, tolerance, encoding, format
// version) is reused, not re-baked, unless --force.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>
#include <variant>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/library.h"
#include "models/registry.h"
#include "models/spec.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/bake.h"
#include "tables/cache.h"
#include "tables/exr_io.h"
#include "tables/preset.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/timing.h"

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
        throw InputError("bake preset: the model spec '" + spec + "' sets " + set +
                         ", which the table's axis and channels set; give the model as ggx or ggx:g2=...");
}

tables::PresetOptions preset_options(const BakeArgs& args) {
  tables::PresetOptions options;
  options.preset = tables::parse_preset(args.preset);
  if (!args.dfg_layout.empty()) {
    if (options.preset != tables::Preset::dfg) throw InputError("--dfg-layout is for bake preset dfg");
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

/// bake preset dfg|kulla-conty --model ggx -o FILE.exr: a format version 3 table.
int bake_preset_table(const BakeArgs& args) {
  if (args.model.empty())
    throw InputError("bake preset needs --model ggx[:g2=...] (the model over the roughness axis)");
  if (args.output.empty()) throw InputError("bake preset needs -o FILE.exr");
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
  std::printf(
      "baked preset %s (%s) of %s, %dx%d %s-centred samples over (%s, cos_theta_i), channels %s, in %.2f s: "
      "lookup error %s (bilinear, validated at %lld points with alpha >= %s, cos_theta_i >= %s; per-texel "
      "error %.3g), %lld unconverged -> %s\n",
      table.preset.c_str(), table.layout.c_str(), table.model.c_str(), table.axes[0].count, table.axes[1].count,
      to_string(table.grid), table.axes[0].name.c_str(), channels.c_str(), seconds, lookup.c_str(), table.lookup_checks,
      format_number(tables::kMinValidatedAlpha).c_str(), format_number(tables::kMinValidatedMu).c_str(),
      table.node_error, unconverged, args.output.c_str());
  if (unconverged > 0)
    std::cerr << "ganzfeld: warning: " << unconverged << " texels missed tolerance " << format_number(table.tolerance)
              << "; their achieved error is stored\n";
  return 0;
}

/// What `bake model` asks for: a fixed grid (--res and the grid's flags) or an error target
/// (--max-error and the target's flags); the flag set lets only one kind's flags through.
tables::BakeRequest model_request(const BakeArgs& args, const Model& model, Law law) {
  scene::TableOptions defaults;
  defaults.tolerance = kModelTol;
  const tables::BakeRequest request = args.table.options(defaults).request(law);
  if (const auto* target = std::get_if<tables::TargetBake>(&request)) {
    tables::check_error_target(target->target.lookup_error, target->target.max_bytes, law, target->encoding);
    return request;
  }
  tables::BakeOptions grid = std::get<tables::BakeOptions>(request);
  grid.resolution = tables::parse_resolution(args.res, law);
  if (!args.mapping.empty()) grid.mappings = tables::parse_mappings(args.mapping, law);
  if (!args.interpolation.empty()) grid.interpolation = tables::parse_interpolation(args.interpolation);
  const tables::Frame frame = args.frame.empty() ? tables::Frame::cosines : tables::parse_frame(args.frame);
  if (frame != tables::Frame::cosines) {
    if (law != Law::g)
      throw InputError({Named{"frame", to_string(frame)}, " is for law g; h and a tables use the cosines frame"});
    grid.lobe = tables::lobe_frame_of(model);
    if (!grid.lobe)
      throw InputError({Named{"frame", to_string(frame)},
                        ": model '" + model.spec() +
                            "' hints no lobe at the mirror direction or at j to "
                            "follow; use ",
                        Named{"frame", "cosines"}});
    grid.warped = frame == tables::Frame::warped;
  }
  if (!args.filter.empty()) {
    grid.filter = tables::parse_filter(args.filter);
    if (grid.filter == tables::Filter::hardware && grid.interpolation == tables::Interpolation::catmull_rom)
      throw InputError({Named{"filter", "hardware"}, " is validated for ", Named{"interpolation", "linear"}, " and ",
                        Named{"interpolation", "b-spline"}, " only"});
  }
  if (args.checks) grid.random_checks = *args.checks;
  return grid;
}

int bake_one(const BakeArgs& args) {
  // Everything is checked before the (possibly long) bake.
  if (args.model.empty()) throw InputError("bake model needs the model spec, e.g. bake model specular:alpha=8");
  if (args.law.empty()) throw InputError("bake model needs --law g|h|a");
  args.table.check_target_parts();
  if (args.res.empty() && !args.table.max_error)
    throw InputError("bake model needs --res N[xN[xN]] (a fixed grid) or --max-error E (an error target)");
  if (args.output.empty()) throw InputError("bake model needs -o FILE.exr");
  const Law law = tables::parse_tabulated_law("--law", args.law);
  const ModelPtr model = parse_model(args.model);
  tables::BakeRequest request = model_request(args, *model, law);
  tables::table_key(*model, law, request);  // refuses bad axes now
  check_writable(args.output);
  attach_progress(tables::common(request), args.quiet, law, model->spec());

  const tables::CacheResult r =
      tables::bake_or_reuse(args.output, *model, law, request, shell_line(args.argv), args.force);
  const tables::Table& table = r.table;
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"tables", {shapes::table_json(r.path, r.table, r.status, r.seconds)}}}.dump(2)
              << "\n";
  } else if (r.status == tables::CacheStatus::reused) {
    std::cerr << "ganzfeld: reused " << args.output << ": it already holds " << to_string(law) << " of " << table.model
              << " with the same axes, tolerance and encoding (--force re-bakes)\n";
  } else {
    std::string nodes;
    for (const tables::Axis& a : table.axes) nodes += (nodes.empty() ? "" : "x") + std::to_string(a.count);
    if (table.target_error > 0.0)
      std::printf("target lookup error %s within %llu value bytes%s: %s\n", format_number(table.target_error).c_str(),
                  static_cast<unsigned long long>(table.target_bytes),
                  table.target_fetches ? (" and " + std::to_string(table.target_fetches) + " fetches").c_str() : "",
                  tables::misses_target(table) ? "missed (best effort: the most accurate table found)" : "met");
    std::printf(
        "baked %s of %s, %s nodes (%s frame, %s, %s filter: %d fetches per lookup, %zu entries, %s, %llu value "
        "bytes) in %.2f s: lookup error %.3g (validated at %lld points%s; node error %.3g), %lld unconverged -> %s\n",
        to_string(law), table.model.c_str(), nodes.c_str(), to_string(table.frame), to_string(table.interpolation),
        to_string(table.filter), tables::fetches(table), table.entries(), to_string(table.encoding),
        static_cast<unsigned long long>(tables::value_bytes(table)), r.seconds, table.lookup_error,
        table.interpolation_checks,
        table.min_cos_j > 0.0 ? (" with j·n >= " + format_number(table.min_cos_j)).c_str() : "", table.node_error,
        table.unconverged, args.output.c_str());
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
  return static_cast<std::size_t>(
      std::count_if(plan.tables.begin(), plan.tables.end(),
                    [](const scene::PlannedTable& t) { return t.status == tables::CacheStatus::baked; }));
}

int bake_scene(const BakeArgs& args) {
  if (args.out_dir.empty()) throw InputError("bake scene needs --out DIR (the table cache directory)");
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
  if (args.out_dir.empty()) throw InputError("bake library needs --out DIR (the table cache directory)");
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
    std::cout << nlohmann::ordered_json{{"shard", name}, {"library_tables", all.size()}, {"tables", tables_json(plan)}}
                     .dump(2)
              << "\n";
  } else {
    const std::size_t baked = baked_count(plan);
    std::printf("shard %s: %zu of the library's %zu tables in %s: %zu baked, %zu reused\n", name.c_str(),
                plan.tables.size(), all.size(), dir.c_str(), baked, plan.tables.size() - baked);
  }
  return 0;
}

}  // namespace

std::vector<std::string> bake_alias(const std::vector<std::string>& words) {
  if (words.size() < 3 || words[1] != "bake" || words[2].empty() || words[2][0] != '-') return words;
  auto given = [&](const std::string& flag) {
    return std::any_of(words.begin() + 2, words.end(),
                       [&](const std::string& w) { return w == flag || w.rfind(flag + "=", 0) == 0; });
  };
  // The old dispatch: --preset first (it took --model too), then --scene, --library, --model.
  for (const char* kind : {"preset", "scene", "library", "model"})
    if (given(std::string("--") + kind)) {
      std::vector<std::string> out = words;
      out.insert(out.begin() + 2, kind);
      return out;
    }
  return words;
}

namespace {

/// -o FILE.exr, --force, --quiet, --json: the flags of the jobs that write one table.
void add_output_flags(CLI::App& cmd, BakeArgs& args) {
  cmd.add_option("-o,--output", args.output, "the table to write, FILE.exr (written atomically)");
  cmd.add_flag("--force", args.force, "bake even when the file already holds exactly this table");
}

/// --out DIR: the cache directory of the jobs that bake many tables.
void add_cache_flags(CLI::App& cmd, BakeArgs& args) {
  cmd.add_option("--out", args.out_dir,
                 "the cache directory (created if its parent exists); file names are SPEC.LAW.HASH.exr");
  cmd.add_flag("--force", args.force, "bake even when the cache already holds exactly a table");
}

void add_quiet_flag(CLI::App& cmd, BakeArgs& args) {
  cmd.add_flag("--quiet", args.quiet, "no progress bar (it is shown only when stderr is a terminal)");
}

/// `bake model`: one law of one model, on a fixed grid or to an error target.
void add_model_job(CLI::App& bake, Action& action, const std::shared_ptr<BakeArgs>& args) {
  auto* cmd = bake.add_subcommand(
      "model",
      "one law (g, h, a) of one model into an OpenEXR table with per-entry error: on a fixed grid (--res, with "
      "--mapping, --frame, --interpolation, --filter, --checks, --tol) or to an error target (--max-error, with "
      "--max-bytes, --fetches, --best-effort)");
  cmd->add_option("spec,--model", args->model, "the model spec, e.g. specular:alpha=8 (see `ganzfeld models`)");
  cmd->add_option("--law", args->law, "g (vignetting, 3-D), h (darkening, 1-D) or a (albedo, 1-D)");
  add_output_flags(*cmd, *args);
  CLI::Option* res = cmd->add_option(
      "--res", args->res,
      "fixed grid: nodes per axis, N or NIxNJxNPHI for g (axes cos_theta_i, cos_theta_j, phi); each >= 2");
  std::vector<CLI::Option*> grid{res};
  grid.push_back(cmd->add_option("--mapping", args->mapping,
                                 "fixed grid: axis mappings, M or MxMxM for g (M = linear, sqrt, cos; default: the "
                                 "law's defaults)"));
  grid.push_back(cmd->add_option(
      "--frame", args->frame,
      "fixed grid: g axes, cosines (i·n, j·n, phi; default), lobe (theta_j, psi, beta about the lobe's peak) or "
      "warped (theta_j, the sky edge's warped offset from the lobe, beta; docs/lut-format.md)"));
  grid.push_back(
      cmd->add_option("--filter", args->filter,
                      "fixed grid: the lookup its bound covers, texel-fetch (default) or hardware (one "
                      "GPU-filtered fetch per linear blend, 8-bit weights; linear and b-spline interpolation)"));
  grid.push_back(
      cmd->add_option("--interpolation", args->interpolation,
                      "fixed grid: lookup, linear (default), catmull-rom or b-spline (stores the cubic B-spline's "
                      "coefficients; 2 hardware-filtered fetches per axis)"));
  grid.push_back(cmd->add_option(
      "--checks", args->checks,
      "fixed grid: seeded random validation points (besides the cell centres) against direct cubature"));
  scene::TableOptions defaults;
  defaults.tolerance = kModelTol;
  const TableOptionArgs::Added added = args->table.add_to(*cmd, defaults, false);
  grid.push_back(added.tol);
  for (CLI::Option* target : {added.max_error, added.max_bytes, added.fetches})
    for (CLI::Option* fixed : grid) target->excludes(fixed);
  add_quiet_flag(*cmd, *args);
  add_json_flag(*cmd, args->json, "{\"tables\": [{path, model, law, status}]}");
  cmd->callback([&action, args] { action = [args] { return bake_one(*args); }; });
}

/// `bake preset`: a table over a roughness axis, as engines read it.
void add_preset_job(CLI::App& bake, Action& action, const std::shared_ptr<BakeArgs>& args) {
  auto* cmd = bake.add_subcommand(
      "preset",
      "a table over a roughness axis, as engines read it: dfg (split-sum DFG) or kulla-conty (E, E_avg) of "
      "--model ggx[:g2=...]; docs/lut-format.md, version 3");
  cmd->add_option("preset,--preset", args->preset, "dfg or kulla-conty");
  cmd->add_option("--model", args->model, "ggx or ggx:g2=... (the axis and the channels set alpha and f0)");
  cmd->add_option("--res", args->res, "samples per axis, N or NxN (roughness x cos_theta_i)");
  cmd->add_option("--dfg-layout", args->dfg_layout,
                  "dfg channels: filament (default: dfg_fc, dfg_e, charlie) or ue4 (scale, bias)");
  cmd->add_option("--axis", args->axis, "the parameter axis, roughness (default; alpha = R^2) or alpha");
  cmd->add_option("--grid", args->grid,
                  "texel (default; sample k at (k + 0.5)/N, what a GPU lookup reads) or node (k/(N - 1))");
  cmd->add_option(
      "--tol", args->table.tol,
      "absolute tolerance of every texel's cubature (default " + format_number(tables::kPresetTolerance) + ")");
  cmd->add_option("--encoding", args->table.encoding, "stored precision: float (default), half or unorm16");
  cmd->add_option("--max-evals", args->table.max_evaluations,
                  "evaluation budget per texel; beyond it the texel is kept and counted as unconverged");
  cmd->add_option("-o,--output", args->output, "the table to write, FILE.exr (written atomically)");
  add_quiet_flag(*cmd, *args);
  cmd->callback([&action, args] { action = [args] { return bake_preset_table(*args); }; });
}

/// `bake scene`: every table a scene needs, into a cache directory.
void add_scene_job(CLI::App& bake, Action& action, const std::shared_ptr<BakeArgs>& args) {
  auto* cmd = bake.add_subcommand("scene", "every table a scene needs into a cache directory");
  cmd->add_option("scene,--scene", args->scene, "the scene file, SCENE.json (e.g. examples/default.json)");
  add_cache_flags(*cmd, *args);
  args->table.add_to(*cmd, scene::TableOptions::scene_defaults());
  add_quiet_flag(*cmd, *args);
  add_json_flag(*cmd, args->json, "{\"tables\": [{path, model, law, status}, ...]}");
  cmd->callback([&action, args] { action = [args] { return bake_scene(*args); }; });
}

/// `bake library`: one shard of a material library's tables, into a cache directory.
void add_library_job(CLI::App& bake, Action& action, const std::shared_ptr<BakeArgs>& args) {
  auto* cmd = bake.add_subcommand(
      "library", "one shard of a material library's tables into a cache directory (docs/scale-out.md)");
  cmd->add_option("library,--library", args->library,
                  "LIB.json, groups of model specs x laws x accuracies (the accuracies go in the library)");
  cmd->add_option("--shard", args->shard,
                  "bake only shard K of N (K/N, 0 <= K < N; default 0/1, all); the N shards are disjoint and "
                  "together are the whole library");
  add_cache_flags(*cmd, *args);
  add_quiet_flag(*cmd, *args);
  add_json_flag(*cmd, args->json, "{\"shard\", \"library_tables\", \"tables\": [...]}");
  cmd->callback([&action, args] { action = [args] { return bake_library(*args); }; });
}

}  // namespace

void add_bake_command(CLI::App& app, Action& action, int argc, const char* const* argv) {
  auto* cmd = app.add_subcommand(
      "bake",
      "bake tables: `bake model` (one law of one model), `bake preset` (a roughness-axis table), `bake scene` "
      "(a scene's tables) or `bake library` (a library's); a file that already holds exactly the requested table is "
      "reused. The spellings bake --model/--preset/--scene/--library are aliases of these");
  auto args = std::make_shared<BakeArgs>();
  args->argv.assign(argv, argv + argc);
  add_model_job(*cmd, action, args);
  add_preset_job(*cmd, action, args);
  add_scene_job(*cmd, action, args);
  add_library_job(*cmd, action, args);
  cmd->callback([&action, cmd] {
    if (cmd->get_subcommands().empty())
      action = []() -> int {
        throw InputError(
            "bake needs a job: bake model SPEC --law g|h|a (--res N | --max-error E) -o FILE.exr, "
            "bake preset dfg|kulla-conty --model ggx -o FILE.exr, bake scene SCENE.json --out DIR or "
            "bake library LIB.json --out DIR [--shard K/N]");
      };
  });
}

}  // namespace ganzfeld::cli
