#include "scene/json_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/error.h"

namespace ganzfeld::scene {

namespace {

namespace fs = std::filesystem;

/// nlohmann's message without its "[json.exception.KIND.N] " prefix.
std::string without_prefix(const std::string& what) {
  const auto bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

}  // namespace

nlohmann::ordered_json read_json_file(const std::string& kind, const std::string& path,
                                      const std::optional<std::string>& text) {
  const auto refuse = [&](const std::string& why) { return InputError(kind + " '" + path + "': " + why); };
  std::string content;
  if (text) {
    content = *text;
  } else {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw refuse("no such file");
    if (!fs::is_regular_file(path, ec)) throw refuse("not a regular file");
    std::ifstream in(path, std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (!in || in.bad()) throw refuse("cannot be read");
    content = buffer.str();
  }
  try {
    return nlohmann::ordered_json::parse(content);
  } catch (const nlohmann::ordered_json::parse_error& e) {
    // "parse error at line L, column C: ..."
    throw refuse("malformed JSON: " + without_prefix(e.what()) + " (byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::ordered_json::exception& e) {
    // e.g. "number overflow parsing '1e999'": JSON numbers must be finite.
    throw refuse("malformed JSON: " + without_prefix(e.what()) + " (numbers must be finite)");
  }
}

}  // namespace ganzfeld::scene
