// The measured data files `ganzfeld serve --data DIR` exposes by name (docs/serve.md). DIR is read
// once, at start: each regular file directly in it whose bytes are a MERL file, a tabulated BRDF or
// a Beard–Maxwell first-surface table (models/measured.h, models/beard_maxwell.h) is listed under
// its name; anything else is skipped with the reason. A request names a file only by that name
// (merl:file=NAME); the service substitutes the file's path itself, so no request can name a path,
// and a name it did not list is 404. The model built from it keys its tables by the digest of the
// bytes it read (Model::content_digest, tables/cache.h): the cache is content-addressed whatever
// the name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/spec.h"

namespace ganzfeld::serve {

struct DataFile {
  std::string name;    ///< the file's name in DIR: what requests say
  std::string model;   ///< the registered model that reads it: merl, tabulated or beard-maxwell
  std::string path;    ///< DIR/name: only the service sees it
  std::string digest;  ///< util::content_digest of the bytes read at start
  std::uint64_t bytes = 0;
  bool isotropic = true;
};

class DataFiles {
 public:
  /// No --data: every spec naming a file is refused (400), as without this class.
  DataFiles() = default;
  /// Lists DIR; throws InputError (one line: exit 2) when it does not exist or is not a directory.
  static DataFiles scan(const std::string& dir);

  bool enabled() const { return enabled_; }
  const std::vector<DataFile>& files() const { return files_; }
  /// "NAME: why" for every file of DIR not listed.
  const std::vector<std::string>& skipped() const { return skipped_; }

  /// The spec with every term's file=NAME replaced by that file's path. Throws RequestError:
  /// 400 without --data, 404 for a NAME not listed (naming those that are).
  Spec resolve(Spec spec) const;
  /// The reverse, for what replies show: every listed path replaced by its name.
  std::string display(const std::string& spec) const;

  /// GET /api/data: {"data": bool, "files": [{name, model, spec, isotropic, bytes, digest}], "skipped": [...]}.
  nlohmann::ordered_json listing() const;

 private:
  bool enabled_ = false;
  std::vector<DataFile> files_;
  std::vector<std::string> skipped_;
};

}  // namespace ganzfeld::serve
