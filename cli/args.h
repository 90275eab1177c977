// Shared command-line plumbing: direction flags, tolerances, the table options every scene command
// takes, table stores, JSON shapes of tables, stamped command lines and progress.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "integrate/laws.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "shapes/json.h"
#include "tables/bake.h"
#include "tables/cache.h"
#include "tables/to_error.h"

namespace ganzfeld::cli {

/// The direction flags: --i/--j X,Y,Z or --theta-i/--theta-j/--phi in degrees.
struct DirectionArgs {
  std::string i_text, j_text;
  std::optional<double> theta_i, theta_j;
  double phi_deg = 0.0;
  void add_to(CLI::App& app);
  /// The incident direction / sky pole; `allow_below` for the law of vignetting (i·n < 0).
  Vec3 incident(Law law) const;
  Vec3 outgoing(Law law) const;
};

/// --alpha A / --roughness R: a value of a model's roughness parameter (eval: it overrides the
/// spec's; sample: the point on a parameter table's axis).
struct ParameterArgs {
  std::optional<double> alpha, roughness;
  void add_to(CLI::App& app);
  /// The flag given ("alpha" or "roughness") and its value, validated: alpha in (0, 1],
  /// roughness in [0, 1], finite; nothing when neither is given; both given is refused.
  std::optional<std::pair<std::string, double>> given() const;
};

/// --json: "print one JSON document", with its shape when given.
void add_json_flag(CLI::App& cmd, bool& json, const std::string& shape = "");
/// --model SPEC, required: the model of a command about one model (eval, figure, tradeoff).
void add_model_option(CLI::App& cmd, std::string& spec);
/// FILE, required: a table written by `ganzfeld bake` (info, sample).
void add_table_argument(CLI::App& cmd, std::string& path);

/// Parses "X,Y,Z" into a normalized vector; throws InputError naming the flag and the value.
Vec3 parse_vector(const std::string& flag, const std::string& text);

/// Refuses non-finite, non-positive or absurd tolerances with a one-line message.
void validate_tolerance(double tol);

/// Words joined into a line a POSIX shell reproduces: words with anything but [A-Za-z0-9_./:=,+-]
/// are single-quoted. The first word is written as `ganzfeld`.
std::string shell_line(const std::vector<std::string>& words);

/// A progress bar on stderr for the bake of `law` of `spec`, when stderr is a terminal and not `quiet`.
void attach_progress(tables::BakeCommon& options, bool quiet, Law law, const std::string& spec);

/// The table cache directory named by `flag` (--out, --cache): created if its parent exists;
/// a missing parent, a non-directory or an unwritable directory is refused. Returns it.
std::string prepare_directory(const std::string& flag, const std::string& text);

/// Refuses an evaluation budget below 1000 per entry.
void check_max_evaluations(long long n);

/// The table options of every command that takes a scene (bake scene, render, export-glsl
/// --scene) and of figure: --res-g, --res-h, --tol, --encoding, --max-evals. One parser and one
/// set of defaults (scene::TableOptions), so that the commands reach the same cache entries.
struct TableOptionArgs {
  std::string res_g, res_h, encoding;
  std::optional<double> tol;
  std::optional<long long> max_evaluations;
  std::optional<double> max_error;
  std::optional<unsigned long long> max_bytes;
  std::optional<long long> fetches;
  bool best_effort = false;
  /// The options add_to registered (the accuracy flags that exclude or need one another).
  struct Added {
    CLI::Option *tol, *max_error, *max_bytes, *fetches;
  };
  /// Registers the flags; `defaults` is what --help shows and what unset flags mean. Without
  /// `per_law_grids`, no --res-g and --res-h (one table's grid is its own flag).
  Added add_to(CLI::App& app, const scene::TableOptions& defaults, bool per_law_grids = true);
  /// The options, validated (InputError naming the parameter: res_g, max_error, ...; the command line
  /// spells it as a flag, a library file as its key); unset flags take `defaults`. Defaults that
  /// bake to an error (scene_defaults) give way to a fixed resolution when res_g, res_h or tol is given.
  scene::TableOptions options(const scene::TableOptions& defaults) const;
  /// Refuses --max-bytes, --fetches and --best-effort without --max-error (tables::needs_target).
  void check_target_parts() const;
};

/// Where a command's scene tables come from: the cache directory `cache_dir` (already prepared)
/// or memory when it is empty; progress bars unless `quiet`, each file stamped with the bake
/// command that reproduces it.
scene::TableStore table_store(const std::string& cache_dir, bool quiet, bool force = false);

/// --cache DIR of the commands that bake a scene's tables for their own use (render, figure,
/// export-glsl --scene): the files `bake scene SCENE --out DIR` makes; memory when not given.
struct CacheArgs {
  std::string dir;
  /// Registers --cache; `when` opens its help, e.g. "with --scene: ".
  void add_to(CLI::App& app, const std::string& when = "");
  /// table_store of the directory, prepared (prepare_directory), or of memory.
  scene::TableStore store(bool quiet) const;
};

/// shapes::table_json of every table of the plan.
nlohmann::ordered_json tables_json(const scene::ShadingPlan& plan);

/// Warns on stderr about a freshly baked table with entries that missed the tolerance.
void warn_unconverged(const tables::Table& table, tables::CacheStatus status);
/// warn_unconverged for every table of the plan.
void warn_unconverged(const scene::ShadingPlan& plan);

}  // namespace ganzfeld::cli
