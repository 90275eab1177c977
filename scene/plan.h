// The one path from a scene to pixels: scene + table options → the
// tables it needs → cache lookups or bakes → a shading plan that the rasterizer, the GLSL
// exporter, the figures and the benchmark all consume. Every command that takes a scene reads
// the same TableOptions (cli/args.h: add_table_options), so they all reach the same cache entries.
//
// The laws are linear in f, so tables are per lobe, and the light fields decide which laws are
// looked up (K&P, "Extended sources"):
//   collimated light     H0 (i·n) f(i, j)   no table (f is evaluated directly)
//   hemispherical sky    N g(i, j, n)       g of every lobe of every material an object uses
//   Ganzfeld             N h(j, n)          h of every such lobe
// Lambert lobes never need a table: h = 1 and g = (1 + i·n)/2 in closed form (K&P).
// Anisotropic lobes get none either: their g would need a fourth axis (the azimuth of j from the
// tangent); they are computed directly by cubature per pixel instead.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "integrate/laws.h"
#include "scene/scene.h"
#include "tables/bake.h"
#include "tables/cache.h"
#include "tables/table.h"

namespace ganzfeld::scene {

/// The options of a scene's tables, with the defaults every command shares: a fixed grid per law
/// (resolution_g, resolution_h, tolerance) or, when `target` is set, an error target for every
/// table instead (the grid fields are then not read: request() makes a tables::TargetBake).
struct TableOptions {
  std::vector<int> resolution_g{32, 32, 16};
  std::vector<int> resolution_h{128};
  double tolerance = 1e-8;  ///< absolute tolerance of every entry's cubature
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  tables::Encoding encoding = tables::Encoding::single;
  /// Every table baked to this lookup error (tables/to_error.h), value-byte cap and fetch budget.
  std::optional<tables::ErrorTarget> target = std::nullopt;
  /// The bake request of law g or h (no progress callback).
  tables::BakeRequest request(Law law) const;
  /// What the scene commands (bake scene, render, export-glsl --scene) bake when no accuracy
  /// option is given: every table to lookup error kSceneTargetError at one hardware-filtered fetch
  /// per law in at most kSceneMaxBytes (docs/lut-format.md, "Baking to an error"), best effort:
  /// where one fetch does not reach it, the most accurate one-fetch table found, its stated error
  /// the miss. The resolutions above remain what --res-g and --res-h replace.
  static TableOptions scene_defaults();
};
inline constexpr double kSceneTargetError = 1e-3;
/// The fetch budget of the scene defaults: one fetch per law, the cost Koenderink & Pont promise
/// (that of Lambert's surface under a point source with an ambient term).
inline constexpr int kSceneFetches = 1;
/// The value-byte cap of each table of the scene defaults: where one fetch misses the target
/// (GGX), the best-effort search ends at a table this size instead of growing to megabytes.
inline constexpr std::uint64_t kSceneMaxBytes = std::uint64_t{512} << 10;
/// The fetch budget of a scene's explicit --max-error without --fetches: every scheme's fetches
/// (Catmull–Rom's 64 for g), searched fewest first, so a target one fetch cannot reach is met by
/// the next scheme.
inline constexpr int kSceneSearchFetches = 64;

/// Which light fields a set of lights contains.
struct LightFields {
  bool collimated = false, sky = false, ganzfeld = false;
};
LightFields light_fields(const std::vector<Light>& lights);

/// How a lobe's law g or h is obtained.
enum class LawOrigin {
  none,         ///< the lights do not need it
  closed_form,  ///< Lambert: g = (1 + i·n)/2, h = 1
  table,        ///< a baked table (TableRequest)
  direct,       ///< cubature per pixel (anisotropic lobes, or `render --direct`)
};

/// How law g or h of a lobe (of canonical spec `spec`) is obtained under `fields`, when tables
/// are allowed.
LawOrigin law_origin(const Model& model, Law law, const LightFields& fields);

struct TableRequest {
  std::string spec;  ///< canonical spec of a single (non-mixture) model, Model::spec()
  Law law = Law::h;  ///< g or h
  ModelPtr model;
  tables::BakeRequest options;
  friend bool operator==(const TableRequest& a, const TableRequest& b) { return a.spec == b.spec && a.law == b.law; }
};

/// The tables the scene needs, deduplicated, in a deterministic order: g before h, then the
/// order of first use (materials in file order, lobes in material order). Materials no object
/// uses need nothing; a scene lit only by collimated light needs nothing.
std::vector<TableRequest> tables_needed(const Scene& scene, const TableOptions& options = {});

/// The words of the single-table `ganzfeld bake` command that reproduces the cache entry of
/// `request` at `path` (stamped into the file).
std::vector<std::string> bake_command(const TableRequest& request, const std::string& path);

struct PlannedTable;

/// Where tables come from: a cache directory (reused when an entry matches exactly, else baked
/// and stored), or memory (baked, not stored) when `cache_dir` is empty.
struct TableStore {
  std::string cache_dir;
  bool force = false;  ///< bake even when the cache holds the table
  /// Joins command words into the stamped command line (cli's shell quoting); may be empty.
  std::function<std::string(const std::vector<std::string>&)> command_line;
  /// Called before each bake so the caller can attach progress to the options.
  std::function<void(TableRequest&)> before_bake;
  /// When set, obtains every table instead of the above (the service routes a scene's tables
  /// through its bounded, single-flight bakery: serve/service.h).
  std::function<PlannedTable(TableRequest)> obtain;
};

/// One table of the plan, as obtained.
struct PlannedTable {
  TableRequest request;
  std::shared_ptr<const tables::Table> table;
  std::string path;  ///< the cache file; empty for an in-memory table
  tables::CacheStatus status = tables::CacheStatus::baked;
  double seconds = 0.0;  ///< baking time (0 when reused)
};

/// One lobe, ready to shade: where its g and h come from and, for tables, the tables.
struct PlannedLobe {
  double weight = 1.0;
  Rgb color{1, 1, 1};
  std::string spec;
  ModelPtr model;
  LawOrigin g = LawOrigin::none, h = LawOrigin::none;
  std::shared_ptr<const tables::Table> g_table, h_table;  ///< set when g/h is LawOrigin::table
};
using PlannedMaterial = std::vector<PlannedLobe>;

struct ShadingPlan {
  LightFields fields;
  std::vector<PlannedTable> tables;        ///< in tables_needed order
  std::vector<PlannedMaterial> materials;  ///< one per scene material (unused ones too)
  std::vector<bool> material_used;         ///< per material: some object uses it
};

/// One table obtained from `store`: reused from its cache file when that holds exactly this
/// table, else baked (and stored when the store has a directory).
PlannedTable obtain_table(TableRequest request, const TableStore& store);

/// The plan of `scene`: its tables obtained from `store`; with `direct`, no tables at all (every
/// non-Lambert law is LawOrigin::direct).
ShadingPlan plan_shading(const Scene& scene, const TableOptions& options, const TableStore& store, bool direct = false);

/// The plan of one material under `lights` (no objects: the material counts as used), for
/// figures and benchmarks that shade a material without a scene file.
ShadingPlan plan_material(const Material& material, const std::vector<Light>& lights, const TableOptions& options,
                          const TableStore& store);

/// A material of the lobes of a (mixture) spec, white lobes.
Material material_of(const std::string& spec);

}  // namespace ganzfeld::scene
