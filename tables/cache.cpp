#include "tables/cache.h"
#include "util/atomic_file.h"

#include <cstdio>
#include <filesystem>

#include "models/registry.h"
#include "models/spec.h"
#include "tables/exr_io.h"
#include "tables/to_error.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/timing.h"

namespace ganzfeld::tables {

namespace {

/// Longest spec prefix kept in a file name (the hash keeps names unique).
constexpr std::size_t kMaxNameSpec = 80;

}  // namespace

TableKey table_key(const Model& model, Law law, const BakeRequest& request) {
  TableKey key;
  key.model = spec_without_paths(model.spec());
  key.content = model.content_digest();
  key.law = law;
  key.encoding = common(request).encoding;
  if (const TargetBake* bake = std::get_if<TargetBake>(&request)) {
    const ErrorTarget& target = bake->target;
    check_error_target(target.lookup_error, target.max_bytes, law, bake->encoding);
    key.target_error = target.lookup_error;
    key.target_bytes = target.max_bytes ? target.max_bytes : kDefaultMaxValueBytes;
    if (target.max_fetches != 0) check_fetch_budget(target.max_fetches);
    key.target_fetches = target.max_fetches;
    key.best_effort = target.best_effort;
    return key;
  }
  const BakeOptions& options = std::get<BakeOptions>(request);
  key.axes = bake_axes(law, options);
  key.tolerance = options.tolerance;
  key.interpolation = options.interpolation;
  key.frame = options.lobe ? (options.warped ? Frame::warped : Frame::lobe) : Frame::cosines;
  key.peak = options.lobe ? options.lobe->peak : PeakKind::mirror;
  key.filter = options.filter;
  return key;
}

TableKey table_key(const Table& table) {
  TableKey key;
  key.model = spec_without_paths(table.model);
  key.content = table.model_content;
  key.law = table.law;
  key.encoding = table.encoding;
  if (table.target_error > 0.0) {
    key.target_error = table.target_error;
    key.target_bytes = table.target_bytes;
    key.target_fetches = table.target_fetches;
    return key;
  }
  key.axes = table.axes;
  key.tolerance = table.tolerance;
  key.interpolation = table.interpolation;
  key.frame = table.frame;
  key.peak = table.peak;
  key.filter = table.filter;
  return key;
}

std::string key_text(const TableKey& key) {
  std::string text = "ganzfeld-table format=" + std::to_string(key.format_version) + " model=" + key.model;
  if (!key.content.empty()) text += " content=" + key.content;
  text += std::string(" law=") + to_string(key.law);
  if (key.target_error > 0.0)
    return text + " max_error=" + format_number(key.target_error) + " max_bytes=" + std::to_string(key.target_bytes) +
           " encoding=" + to_string(key.encoding) +
           (key.target_fetches ? " fetches=" + std::to_string(key.target_fetches) : std::string());
  text += " axes=";
  for (std::size_t d = 0; d < key.axes.size(); ++d) {
    const Axis& a = key.axes[d];
    text += (d ? ";" : "") + a.name + ":" + format_number(a.min) + ":" + format_number(a.max) + ":" +
            std::to_string(a.count) + ":" + to_string(a.mapping);
    if (a.has_width()) {  // appended in two steps: g++ 12 warns falsely (-Wrestrict) on ":" + std::string&&
      text += ':';
      text += format_number(a.width);
    }
  }
  text += std::string(" tolerance=") + format_number(key.tolerance) + " encoding=" + to_string(key.encoding);
  text += std::string(" interpolation=") + to_string(key.interpolation) + " frame=" + to_string(key.frame);
  if (key.frame != Frame::cosines) text += std::string(" peak=") + to_string(key.peak);
  if (key.filter != Filter::texel_fetch) text += std::string(" filter=") + to_string(key.filter);
  return text;
}

std::string cache_file_name(const TableKey& key) {
  std::string name;
  for (char c : key.model.substr(0, kMaxNameSpec)) {
    const bool keep =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '=' || c == '.' || c == '-';
    name += keep ? c : '_';
  }
  return name + "." + to_string(key.law) + "." + util::hex16(util::fnv1a_64(key_text(key))) + ".exr";
}

bool same_key(const TableKey& a, const TableKey& b) noexcept {
  return a.model == b.model && a.content == b.content && a.law == b.law && a.tolerance == b.tolerance &&
         a.encoding == b.encoding && a.format_version == b.format_version && a.axes == b.axes &&
         a.interpolation == b.interpolation && a.frame == b.frame && a.peak == b.peak &&
         a.target_error == b.target_error && a.target_bytes == b.target_bytes && a.target_fetches == b.target_fetches &&
         a.filter == b.filter;
}

bool same_model(const Table& table, const Model& model) {
  return spec_without_paths(table.model) == spec_without_paths(model.spec()) &&
         table.model_content == model.content_digest();
}

const char* to_string(CacheStatus status) { return status == CacheStatus::reused ? "reused" : "baked"; }

std::optional<Table> read_if_matching(const std::string& path, const TableKey& key, std::string* why) {
  if (why) why->clear();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  std::string reason;
  try {
    Table table = read_table(path);
    if (!same_key(table_key(table), key)) reason = "it holds another table (its metadata is not the key)";
    else if (!key.best_effort && misses_target(table))
      reason = "it misses its target error (a best-effort bake's table)";
    else if (table.values_digest.empty()) reason = "it has no ganzfeld.values_digest to verify its numbers by";
    else return table;
  } catch (const InputError& e) {  // corrupt, truncated or not a table: re-baked by the caller
    reason = e.what();
  }
  if (why) *why = reason;
  return std::nullopt;
}

CacheResult bake_or_reuse(const std::string& path, const Model& model, Law law, const BakeRequest& request,
                          const std::string& command, bool force) {
  const TableKey key = table_key(model, law, request);
  if (!force) {
    if (std::optional<Table> table = read_if_matching(path, key))
      return {path, CacheStatus::reused, std::move(*table), 0.0};
  }
  check_writable(path);
  const util::Stopwatch watch;
  Table table = bake(model, law, request);
  const double seconds = watch.seconds();
  table.command = command;
  write_table(table, path);
  return {path, CacheStatus::baked, std::move(table), seconds};
}

std::string cache_path(const std::string& directory, const Model& model, Law law, const BakeRequest& request) {
  return (std::filesystem::path(directory) / cache_file_name(table_key(model, law, request))).string();
}

}  // namespace ganzfeld::tables
