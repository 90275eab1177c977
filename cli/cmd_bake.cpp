// ganzfeld bake: one law of one model into an OpenEXR table (lut/, docs/lut-format.md), or every
// table a scene needs into a cache directory (lut/plan.h, lut/cache.h). A table whose file
// already carries exactly the requested key (spec, law, axes, tolerance, encoding, format
// version) is reused, not re-baked, unless --force.
#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "laws/error.h"
#include "laws/registry.h"
#include "laws/spec.h"
#include "lut/bake.h"
#include "lut/cache.h"
#include "lut/exr_io.h"
#include "lut/plan.h"
#include "lut/scene.h"

namespace ganzfeld::cli {

namespace {


// Defaults of a scene bake: a scene's tables bake in about a second (the example scene's six
// tables: 1.6 s on 2 cores). Interpolation between nodes dominates the error: for g of
// specular:alpha=8 it is ~5.6e-3 at 25x25x13 (docs/lut-format.md, "Sampling"), somewhat less
// here; sharper lobes need --res-g raised.
// (lut/plan.h: kSceneResG, kSceneResH, kSceneTolerance, shared with `render`.)
const std::string kDefaultResGText = std::to_string(lut::kSceneResG[0]) + "x" + std::to_string(lut::kSceneResG[1]) + "x" +
                                     std::to_string(lut::kSceneResG[2]);
const std::string kDefaultResHText = std::to_string(lut::kSceneResH);
constexpr double kSceneTol = lut::kSceneTolerance;
constexpr double kModelTol = 1e-9;

struct BakeArgs {
  // one table
  std::string model, law, res, output, mapping;
  // a scene's tables
  std::string scene, out_dir, res_g = kDefaultResGText, res_h = kDefaultResHText;
  // both
  std::optional<double> tol;
  std::string encoding = "float";
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  bool quiet = false, json = false, force = false;
  std::vector<std::string> argv;  ///< the command line, stamped into single tables
};

/// parse_resolution with its message naming `flag` instead of --res.
std::vector<int> resolution_for(const std::string& flag, const std::string& text, Law law) {
  try {
    return lut::parse_resolution(text, law);
  } catch (const InputError& e) {
    std::string what = e.what();
    if (what.rfind("--res ", 0) == 0) what = flag + what.substr(5);
    throw InputError(what);
  }
}

void check_max_evaluations(long long n) {
  if (n < 1000) throw InputError("--max-evals=" + std::to_string(n) + " is too small; allowed: >= 1000");
}

nlohmann::ordered_json table_json(const lut::CacheResult& r) {
  return {{"path", r.path},
          {"model", r.table.model},
          {"law", to_string(r.table.law)},
          {"status", lut::to_string(r.status)},
          {"entries", r.table.entries()},
          {"max_error", r.table.max_error},
          {"unconverged", r.table.unconverged},
          {"seconds", r.seconds}};
}

void warn_unconverged(const lut::CacheResult& r, long long max_evaluations) {
  const lut::Table& t = r.table;
  if (r.status != lut::CacheStatus::baked || t.unconverged == 0) return;
  std::cerr << "ganzfeld: warning: " << t.unconverged << " of " << t.entries() << " entries of " << to_string(t.law)
            << " of " << t.model << " did not reach tolerance " << format_number(t.tolerance) << " within "
            << max_evaluations << " evaluations; their achieved error is stored (max error "
            << format_number(t.max_error) << ")\n";
}

int bake_one(const BakeArgs& args) {
  // Everything is checked before the (possibly long) bake.
  if (args.law.empty()) throw InputError("bake --model needs --law g|h|a");
  if (args.res.empty()) throw InputError("bake --model needs --res N[xN[xN]]");
  if (args.output.empty()) throw InputError("bake --model needs -o FILE.exr");
  const Law law = parse_law(args.law);
  if (law != Law::g && law != Law::h && law != Law::a)
    throw InputError("--law " + args.law + " cannot be tabulated; allowed: g, h, a");
  const ModelPtr model = parse_model(args.model);
  const double tol = args.tol.value_or(kModelTol);
  validate_tolerance(tol);
  check_max_evaluations(args.max_evaluations);
  lut::BakeOptions options;
  options.resolution = lut::parse_resolution(args.res, law);
  if (!args.mapping.empty()) options.mappings = lut::parse_mappings(args.mapping, law);
  options.tolerance = tol;
  options.max_evaluations = args.max_evaluations;
  options.encoding = lut::parse_encoding(args.encoding);
  lut::table_key(*model, law, options);  // refuses bad axes now
  lut::check_writable(args.output);
  attach_progress(options, args.quiet, law, model->spec());

  const lut::CacheResult r = lut::bake_or_reuse(args.output, *model, law, options, shell_line(args.argv), args.force);
  const lut::Table& table = r.table;
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"tables", {table_json(r)}}}.dump(2) << "\n";
  } else if (r.status == lut::CacheStatus::reused) {
    std::cerr << "ganzfeld: reused " << args.output << ": it already holds " << to_string(law) << " of "
              << table.model << " with the same axes, tolerance and encoding (--force re-bakes)\n";
  } else {
    std::string nodes;
    for (const lut::Axis& a : table.axes) nodes += (nodes.empty() ? "" : "x") + std::to_string(a.count);
    std::printf("baked %s of %s, %s nodes (%zu entries, %s) in %.2f s: max error %.3g, %lld unconverged -> %s\n",
                to_string(law), table.model.c_str(), nodes.c_str(), table.entries(), lut::to_string(table.encoding),
                r.seconds, table.max_error, table.unconverged, args.output.c_str());
  }
  warn_unconverged(r, args.max_evaluations);
  return 0;
}

int bake_scene(const BakeArgs& args) {
  if (args.out_dir.empty()) throw InputError("bake --scene needs --out DIR (the table cache directory)");
  const double tol = args.tol.value_or(kSceneTol);
  validate_tolerance(tol);
  check_max_evaluations(args.max_evaluations);
  const lut::Encoding encoding = lut::parse_encoding(args.encoding);
  const std::vector<int> res_g = resolution_for("--res-g", args.res_g, Law::g);
  const std::vector<int> res_h = resolution_for("--res-h", args.res_h, Law::h);
  const Scene scene = load_scene(args.scene);
  const std::vector<lut::TableRequest> requests = lut::tables_needed(scene);
  const std::string dir = prepare_directory("--out", args.out_dir);

  nlohmann::ordered_json tables = nlohmann::ordered_json::array();
  int baked = 0;
  for (const lut::TableRequest& request : requests) {
    lut::BakeOptions options;
    options.resolution = request.law == Law::g ? res_g : res_h;
    options.tolerance = tol;
    options.max_evaluations = args.max_evaluations;
    options.encoding = encoding;
    attach_progress(options, args.quiet, request.law, request.spec);
    const lut::CacheResult r = bake_into_cache(dir, request, options, args.force);
    baked += r.status == lut::CacheStatus::baked;
    tables.push_back(table_json(r));
    if (!args.json)
      std::printf("%s %s of %s, %s nodes, max error %.3g -> %s\n", lut::to_string(r.status), to_string(request.law),
                  request.spec.c_str(), lut::resolution_text(options.resolution).c_str(), r.table.max_error, r.path.c_str());
    warn_unconverged(r, args.max_evaluations);
  }
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"tables", tables}}.dump(2) << "\n";
  } else if (requests.empty()) {
    std::printf("scene %s needs no tables (only collimated light, or Lambert lobes only)\n", args.scene.c_str());
  } else {
    std::printf("%zu tables in %s: %d baked, %zu reused\n", requests.size(), dir.c_str(), baked,
                requests.size() - static_cast<std::size_t>(baked));
  }
  return 0;
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
  cmd->add_option("-o,--output", args->output, "one table: the table to write, FILE.exr (written atomically)");
  cmd->add_option("--scene", args->scene, "a scene's tables: the scene file, SCENE.json (cli-contract.md)");
  cmd->add_option("--out", args->out_dir,
                  "a scene's tables: the cache directory (created if its parent exists); file names are "
                  "SPEC.LAW.HASH.exr");
  cmd->add_option("--res-g", args->res_g, std::string("a scene's tables: nodes of every g table (default ") +
                                              kDefaultResGText + ")");
  cmd->add_option("--res-h", args->res_h, std::string("a scene's tables: nodes of every h table (default ") +
                                              kDefaultResHText + ")");
  cmd->add_option("--tol", args->tol,
                  "absolute tolerance of every entry's cubature (default 1e-9 for --model, 1e-8 for --scene)");
  cmd->add_option("--max-evals", args->max_evaluations,
                  "evaluation budget per entry; beyond it the entry is kept and counted as unconverged");
  cmd->add_option("--encoding", args->encoding, "stored precision: float (default) or half");
  cmd->add_flag("--force", args->force, "bake even when the file already holds exactly this table");
  cmd->add_flag("--quiet", args->quiet, "no progress bar (it is shown only when stderr is a terminal)");
  cmd->add_flag("--json", args->json, "print one JSON document: {\"tables\": [{path, model, law, status}, ...]}");
  cmd->callback([&action, args, cmd] {
    const bool scene = cmd->count("--scene") > 0, model = cmd->count("--model") > 0;
    action = [args, cmd, scene, model] {
      if (scene && model)
        throw InputError("--scene and --model are mutually exclusive; bake either one table (--model) or a scene's");
      if (!scene && !model)
        throw InputError("bake needs --model SPEC (one table, with --law, --res, -o) or --scene SCENE.json --out DIR");
      const std::vector<std::string> own_model{"--law", "--res", "--mapping", "--output"};
      const std::vector<std::string> own_scene{"--out", "--res-g", "--res-h"};
      for (const std::string& flag : scene ? own_model : own_scene)
        if (cmd->count(flag) > 0)
          throw InputError(flag + " is for " + (scene ? "--model" : "--scene") + " bakes; " +
                           (scene ? "with --scene use --out DIR, --res-g, --res-h"
                                  : "with --model use --law, --res, -o FILE.exr"));
      return scene ? bake_scene(*args) : bake_one(*args);
    };
  });
}

}  // namespace ganzfeld::cli
