#include "serve/data.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>

#include "models/registry.h"
#include "models/spec.h"
#include "serve/request.h"
#include "util/error.h"
#include "util/hash.h"

namespace ganzfeld::serve {

namespace fs = std::filesystem;

namespace {

/// Characters a spec string gives a meaning to: a name holding one could not be written as file=NAME.
constexpr const char* kSpecCharacters = ",+*:=";

/// The registered model that reads `bytes`, from their first bytes and size (models/measured.h,
/// models/beard_maxwell.h); "" for none.
std::string model_of(const std::string& bytes) {
  const auto starts = [&](const char* magic) { return bytes.rfind(magic, 0) == 0; };
  if (starts("ganzfeld-tabulated-brdf")) return "tabulated";
  if (starts("ganzfeld-beard-maxwell-first-surface")) return "beard-maxwell";
  if (bytes.size() == 3 * 4 + 3 * std::size_t{90 * 90 * 180} * 8) return "merl";  // merl::kFileBytes
  return "";
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

DataFiles DataFiles::scan(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError({Named{"data", dir},
                      " is not a directory; expected a directory of measured data files "
                      "(MERL, tabulated, Beard-Maxwell first-surface tables)"});
  DataFiles out;
  out.enabled_ = true;
  std::vector<fs::path> entries;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) entries.push_back(e.path());
  if (ec) throw InputError({Named{"data", dir}, " cannot be read: " + ec.message()});
  std::sort(entries.begin(), entries.end());
  for (const fs::path& path : entries) {
    const std::string name = path.filename().string();
    if (!fs::is_regular_file(path, ec)) {
      out.skipped_.push_back(name + ": not a regular file");
      continue;
    }
    if (name.find_first_of(kSpecCharacters) != std::string::npos || name != std::string(name.c_str()) ||
        name.find_first_of(" \t") != std::string::npos) {
      out.skipped_.push_back(name + ": the name holds a character of spec strings (, + * : = or a space)");
      continue;
    }
    const std::string bytes = read_bytes(path);
    const std::string model = model_of(bytes);
    if (model.empty()) {
      out.skipped_.push_back(name + ": not a MERL, tabulated or Beard-Maxwell first-surface file");
      continue;
    }
    try {
      const ModelPtr m = parse_model(model + ":file=" + path.string());
      out.files_.push_back(
          {name, model, path.string(), util::content_digest_of(bytes), bytes.size(), m->traits().isotropic});
    } catch (const InputError& e) { out.skipped_.push_back(name + ": " + e.what()); }
  }
  return out;
}

Spec DataFiles::resolve(Spec spec) const {
  for (SpecTerm& term : spec.terms) {
    if (term.model.file.empty()) continue;
    if (!enabled_)
      throw RequestError(400, "model '" + spec_text(spec) +
                                  "' names a data file; this service reads no file "
                                  "outside its cache (one started with a data directory serves the measured files in "
                                  "it by name): allowed: analytic models and mixtures (see /api/models)");
    const std::string& name = term.model.file;
    const auto found = std::find_if(files_.begin(), files_.end(), [&](const DataFile& f) { return f.name == name; });
    if (found == files_.end()) {
      std::string names;
      for (const DataFile& f : files_) names += (names.empty() ? "" : ", ") + f.name;
      throw RequestError(404, "no data file '" + name + "' in this service's data directory; available: " +
                                  (names.empty() ? "none" : names) + " (see /api/data)");
    }
    term.model.file = found->path;
  }
  return spec;
}

std::string DataFiles::display(const std::string& spec) const {
  std::string out = spec;
  for (const DataFile& f : files_)
    for (std::size_t at; (at = out.find("file=" + f.path)) != std::string::npos;)
      out.replace(at + 5, f.path.size(), f.name);
  return out;
}

nlohmann::ordered_json DataFiles::listing() const {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const DataFile& f : files_)
    files.push_back({{"name", f.name},
                     {"model", f.model},
                     {"spec", f.model + ":file=" + f.name},
                     {"isotropic", f.isotropic},
                     {"bytes", f.bytes},
                     {"digest", f.digest}});
  return {{"data", enabled_}, {"files", files}, {"skipped", skipped_}};
}

}  // namespace ganzfeld::serve
