// JSON documents read from the files a user writes (scene files, material libraries): one reader,
// so every such file refuses the same way, in one line "KIND 'FILE': why".
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace ganzfeld::scene {

/// The JSON document in the file `path` (or in `text` when given, `path` naming it), keys in file
/// order. Throws InputError "KIND 'PATH': no such file | not a regular file | cannot be read |
/// malformed JSON: ... (byte B)"; numbers must be finite.
nlohmann::ordered_json read_json_file(const std::string& kind, const std::string& path,
                                      const std::optional<std::string>& text = std::nullopt);

}  // namespace ganzfeld::scene
