// The viewer's files (serve/viewer/), compiled into the binary by cmake/embed_assets.cmake: the
// page at / and its script, served by `ganzfeld serve` without reading any file.
#pragma once

#include <string_view>
#include <vector>

namespace ganzfeld::serve {

struct Asset {
  std::string_view path;        ///< the URL path, e.g. "/" or "/viewer.js"
  std::string_view media_type;  ///< Content-Type
  std::string_view body;
};

/// Every embedded file.
const std::vector<Asset>& assets();

/// The asset served at `path`, or nullptr.
const Asset* find_asset(std::string_view path);

}  // namespace ganzfeld::serve
