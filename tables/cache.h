// A cache of baked tables: a table is identified by everything that
// determines its numbers and layout — the model, law, axes (names, ranges, counts, mappings),
// tolerance, encoding and format version. The model is its canonical spec without file paths
// (spec_without_paths) plus the digest of its data files' bytes (Model::content_digest,
// ganzfeld.model_content): a measured model is keyed by what its file holds, not where it lies,
// so new bytes at the same path re-bake, and the same bytes at another path reuse the table
// (which keeps naming the path it was baked from). The key is hashed (64-bit FNV-1a) into a
// readable file name; a file is reused only when it reads cleanly (read_table) and its own
// metadata equals the key exactly, so a corrupt, truncated, stale or colliding file is re-baked
// and atomically replaced (write_table renames a complete temporary file over it). Its numbers
// must match the digest in its header (ganzfeld.values_digest, checked by read_table); a file
// written before the digest existed is re-baked once, so every reused table has been verified.
//
// Not in the key: data file paths, the evaluation budget per entry
// (BakeCommon::max_evaluations, not stored in the file), the command line and the ganzfeld
// version that made the table.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tables/bake.h"
#include "tables/table.h"

namespace ganzfeld::tables {

struct TableKey {
  std::string model;    ///< canonical spec without file paths: spec_without_paths(Model::spec())
  std::string content;  ///< Model::content_digest(): "" for analytic models
  Law law = Law::g;
  std::vector<Axis> axes;
  double tolerance = 0.0;
  Encoding encoding = Encoding::single;
  int format_version = kFormatVersion;
  Interpolation interpolation = Interpolation::linear;
  Frame frame = Frame::cosines;
  PeakKind peak = PeakKind::mirror;  ///< lobe and warped frames
  Filter filter = Filter::texel_fetch;
  /// A --max-error bake is keyed by its target (the baker chooses axes, tolerance, frame and
  /// interpolation, which are then not part of the key): error and value-byte cap.
  double target_error = 0.0;
  std::uint64_t target_bytes = 0;
  int target_fetches = 0;  ///< --fetches (0: no budget)
  /// Not part of the file's key (a table that meets its target serves both): a table that misses
  /// its target, which only a best-effort bake (BakeOptions::best_effort) keeps, serves only those.
  bool best_effort = false;
};

/// The key of the table bake(model, law, request) would make (axes: make_axes). Throws
/// InputError for what bake would refuse about the axes (law, counts, mappings) or the target.
TableKey table_key(const Model& model, Law law, const BakeRequest& request);
/// The key a table read from a file carries.
TableKey table_key(const Table& table);

/// Every field of the key as one line of text, doubles as shortest round-trip text; the content
/// only when there is one, so analytic keys (and their file names) are those of earlier versions.
std::string key_text(const TableKey& key);
/// "SANITIZED-SPEC.LAW.HASH16.exr", e.g. "specular_alpha=8.h.0123456789abcdef.exr": key.model
/// with characters outside [A-Za-z0-9=.-] replaced by '_' (shortened if long), the law, and
/// the 16 hex digits of util::fnv1a_64(key_text(key)).
std::string cache_file_name(const TableKey& key);

/// Exact equality of every field (axes: name, min, max, count, mapping, width).
bool same_key(const TableKey& a, const TableKey& b) noexcept;

/// Whether `table` holds `model` as the cache's key sees it: the same spec apart from file paths,
/// and data files of the same bytes.
bool same_model(const Table& table, const Model& model);

enum class CacheStatus { baked, reused };
const char* to_string(CacheStatus status);  ///< "baked" or "reused"

struct CacheResult {
  std::string path;
  CacheStatus status = CacheStatus::baked;
  Table table;           ///< the table now at `path`
  double seconds = 0.0;  ///< baking time (0 when reused)
};

/// The table at `path` when it exists, reads cleanly (its numbers verified against its digest)
/// and carries exactly `key`; otherwise nothing (no exception for a corrupt or mismatching
/// file). When a file is there but refused, `why` (if given) says why in one line; else "".
std::optional<Table> read_if_matching(const std::string& path, const TableKey& key, std::string* why = nullptr);

/// Reuses the table at `path` if read_if_matching accepts it (and not `force`); otherwise bakes
/// it, stamps `command` into it and writes it atomically over `path`.
CacheResult bake_or_reuse(const std::string& path, const Model& model, Law law, const BakeRequest& request,
                          const std::string& command, bool force = false);

/// The path of this table in the cache `directory`: directory/cache_file_name(key).
std::string cache_path(const std::string& directory, const Model& model, Law law, const BakeRequest& request);

}  // namespace ganzfeld::tables
