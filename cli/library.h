// Material libraries for `ganzfeld bake library LIB.json --out DIR --shard K/N` (docs/scale-out.md):
// a JSON file of groups, each a list of model specs × laws × accuracies, names the tables of a
// library; the tables are the cache entries `bake scene`, `render` and `serve` use (same keys,
// same file names: tables/cache.h), so shards baked anywhere merge by copying files.
//
//   {"groups": [{"models": ["specular:alpha=8", "minnaert:xi=1"], "laws": ["g", "h"],
//                "accuracies": [{}, {"res_g": "16x16x8", "res_h": "64", "tol": 1e-6}, {"max_error": 1e-4}]}]}
//
// An accuracy's keys are the table flags of `bake scene` without their dashes (res_g, res_h,
// tol, encoding, max_evals, max_error, max_bytes), checked by the same parser (TableOptionArgs);
// unset keys take the same defaults (scene::TableOptions), so {} is a scene's default table.
// Laws h and a take res_h (one axis), g takes res_g.
#pragma once

#include <string>
#include <vector>

#include "scene/plan.h"

namespace ganzfeld::cli {

/// Shard `index` of `count` (--shard K/N): 0 <= K < N.
struct Shard {
  int index = 0, count = 1;
};
/// "K/N" in decimal with 0 <= K < N <= kMaxShards; anything else is refused in one line.
Shard parse_shard(const std::string& text);
inline constexpr int kMaxShards = 100000;

/// The tables of the library file `path`: every model × law × accuracy of every group, in file
/// order, once per cache key (two entries naming the same table bake it once). Everything is
/// checked before anything is baked: a malformed file, an unknown key, model or law, a bad
/// accuracy or an anisotropic model is refused (InputError "library 'PATH': WHERE: why").
std::vector<scene::TableRequest> load_library(const std::string& path);

/// The tables of `shard`: the library's tables ordered by decreasing size (tables baked to an
/// error target first, their size being chosen while baking; then by entries; ties in library
/// order) and dealt round-robin, table t to shard t mod N. The N shards are disjoint, their union
/// is the library, and every process computes the same split from the same file.
std::vector<scene::TableRequest> shard_of(const std::vector<scene::TableRequest>& tables, Shard shard);

}  // namespace ganzfeld::cli
