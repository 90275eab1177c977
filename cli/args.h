// Shared command-line plumbing: direction flags and tolerances.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "integrate/laws.h"
#include "lut/bake.h"
#include "lut/cache.h"
#include "lut/plan.h"
#include "lut/scene.h"

namespace ganzfeld::cli {

/// The direction flags of cli-contract.md: --i/--j X,Y,Z or --theta-i/--theta-j/--phi in degrees.
struct DirectionArgs {
  std::string i_text, j_text;
  std::optional<double> theta_i, theta_j;
  double phi_deg = 0.0;
  void add_to(CLI::App& app);
  /// The incident direction / sky pole; `allow_below` for the law of vignetting (i·n < 0).
  Vec3 incident(Law law) const;
  Vec3 outgoing(Law law) const;
};

/// Parses "X,Y,Z" into a normalized vector; throws InputError naming the flag and the value.
Vec3 parse_vector(const std::string& flag, const std::string& text);

/// Refuses non-finite, non-positive or absurd tolerances with a one-line message.
void validate_tolerance(double tol);

/// Words joined into a line a POSIX shell reproduces: words with anything but [A-Za-z0-9_./:=,+-]
/// are single-quoted. The first word is written as `ganzfeld`.
std::string shell_line(const std::vector<std::string>& words);

/// A progress bar on stderr for the bake of `law` of `spec`, when stderr is a terminal and not `quiet`.
void attach_progress(lut::BakeOptions& options, bool quiet, Law law, const std::string& spec);

/// The table cache directory named by `flag` (--out, --cache): created if its parent exists;
/// a missing parent, a non-directory or an unwritable directory is refused. Returns it.
std::string prepare_directory(const std::string& flag, const std::string& text);

/// One table of a scene in the cache directory (lut/cache.h), baked or reused, stamped with the
/// single-table `ganzfeld bake` command that reproduces it: shared by `bake --scene` and `render`.
lut::CacheResult bake_into_cache(const std::string& dir, const lut::TableRequest& request, const lut::BakeOptions& options,
                                 bool force = false);

/// The tables a scene's lights need (lut::tables_needed), with the scene defaults of lut/plan.h
/// at tolerance `tol`: reused from or baked into `cache` (a prepared directory), or baked in
/// memory when `cache` is empty. Warns on stderr about entries that missed the tolerance.
/// Shared by `render` and `export-glsl --scene`.
struct SceneTables {
  std::map<std::pair<std::string, Law>, std::shared_ptr<const lut::Table>> tables;
  nlohmann::ordered_json json = nlohmann::ordered_json::array();  ///< per table: model, law, status, max_error[, path]
};
SceneTables prepare_scene_tables(const Scene& scene, double tol, const std::string& cache, bool quiet);

}  // namespace ganzfeld::cli
