#include "cli/library.h"

#include <algorithm>
#include <charconv>
#include <set>

#include "cli/args.h"
#include "models/registry.h"
#include "scene/json_file.h"
#include "tables/cache.h"
#include "tables/to_error.h"
#include "util/error.h"

namespace ganzfeld::cli {

namespace {

using Json = nlohmann::ordered_json;

/// A decimal integer that is the whole of `text`, or nothing.
std::optional<int> whole_int(std::string_view text) {
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

class LibraryParser {
 public:
  explicit LibraryParser(std::string path) : path_(std::move(path)) {}

  std::vector<scene::TableRequest> parse() {
    const Json doc = scene::read_json_file("library", path_);
    if (!doc.is_object() || doc.size() != 1 || !doc.contains("groups") || !doc["groups"].is_array())
      refuse("top level", "expected {\"groups\": [{\"models\": [...], \"laws\": [...], \"accuracies\": [...]}, ...]}");
    const Json& groups = doc["groups"];
    for (std::size_t k = 0; k < groups.size(); ++k) group(groups[k], "groups[" + std::to_string(k) + "]");
    return std::move(tables_);
  }

 private:
  std::string path_;
  std::vector<scene::TableRequest> tables_;
  std::set<std::string> keys_;  ///< tables::key_text of every table in tables_

  [[noreturn]] void refuse(const std::string& where, const std::string& why) const {
    throw InputError("library '" + path_ + "': " + where + ": " + why);
  }

  /// `what`, rethrowing its InputError with `where` in front and its parameters named as the
  /// file's keys are (max_error, res_g: what `where` holds).
  template <class F>
  auto at(const std::string& where, F&& what) const {
    try {
      return what();
    } catch (const InputError& e) { refuse(where, e.worded(InputError::query_spelling)); }
  }

  /// group[name]: a non-empty array of strings (or, for accuracies, objects; absent: [{}]).
  const Json& list(const Json& group, const std::string& where, const char* name) const {
    static const Json kDefaultAccuracy = Json::array({Json::object()});
    if (!group.contains(name) && std::string(name) == "accuracies") return kDefaultAccuracy;
    if (!group.contains(name) || !group[name].is_array() || group[name].empty())
      refuse(where + "." + name, "expected a non-empty array");
    return group[name];
  }

  std::string text(const Json& value, const std::string& where) const {
    if (!value.is_string()) refuse(where, value.dump() + " is not a string");
    return value.get<std::string>();
  }

  void group(const Json& g, const std::string& where) {
    if (!g.is_object()) refuse(where, "expected an object with keys models, laws, accuracies");
    for (const auto& item : g.items())
      if (item.key() != "models" && item.key() != "laws" && item.key() != "accuracies")
        refuse(where, "unknown key '" + item.key() + "'; allowed: models, laws, accuracies");
    const Json &models = list(g, where, "models"), &laws = list(g, where, "laws"),
               &accuracies = list(g, where, "accuracies");
    std::vector<scene::TableOptions> options;
    for (std::size_t a = 0; a < accuracies.size(); ++a)
      options.push_back(accuracy(accuracies[a], where + ".accuracies[" + std::to_string(a) + "]"));
    for (std::size_t m = 0; m < models.size(); ++m) {
      const std::string at_model = where + ".models[" + std::to_string(m) + "]";
      const ModelPtr model = at(at_model, [&] { return parse_model(text(models[m], at_model)); });
      if (!model->traits().isotropic)
        refuse(at_model, "model '" + model->spec() + "' is anisotropic; tables hold isotropic models only");
      for (std::size_t l = 0; l < laws.size(); ++l) {
        const std::string at_law = where + ".laws[" + std::to_string(l) + "]";
        const Law law = at(at_law, [&] { return tables::parse_tabulated_law("law", text(laws[l], at_law)); });
        for (std::size_t a = 0; a < options.size(); ++a)
          add({model->spec(), law, model, options[a].request(law == Law::g ? Law::g : Law::h)},
              at_model + ", " + at_law + ", accuracies[" + std::to_string(a) + "]");
      }
    }
  }

  /// The options of one accuracy object, through the flags' own parser and defaults.
  scene::TableOptions accuracy(const Json& a, const std::string& where) const {
    if (!a.is_object()) refuse(where, "expected an object such as {\"res_g\": \"32x32x16\", \"res_h\": \"128\"}");
    TableOptionArgs args;
    for (const auto& item : a.items()) {
      const std::string& key = item.key();
      const Json& v = item.value();
      const std::string at_key = where + "." + key;
      const auto number = [&] {
        if (!v.is_number()) refuse(at_key, v.dump() + " is not a number");
        return v.get<double>();
      };
      const auto integer = [&] {
        if (!v.is_number_integer()) refuse(at_key, v.dump() + " is not an integer");
        return v.get<long long>();
      };
      if (key == "res_g") args.res_g = v.is_number_integer() ? v.dump() : text(v, at_key);
      else if (key == "res_h") args.res_h = v.is_number_integer() ? v.dump() : text(v, at_key);
      else if (key == "encoding") args.encoding = text(v, at_key);
      else if (key == "tol") args.tol = number();
      else if (key == "max_error") args.max_error = number();
      else if (key == "max_evals") args.max_evaluations = integer();
      else if (key == "max_bytes") {
        if (integer() < 0) refuse(at_key, v.dump() + " is negative");
        args.max_bytes = static_cast<unsigned long long>(integer());
      } else {
        refuse(where,
               "unknown key '" + key + "'; allowed: res_g, res_h, tol, encoding, max_evals, max_error, max_bytes");
      }
    }
    return at(where, [&] { return args.options(scene::TableOptions{}); });
  }

  /// Adds the table unless the library already has it (same cache key).
  void add(scene::TableRequest request, const std::string& where) {
    const tables::TableKey key =
        at(where, [&] { return tables::table_key(*request.model, request.law, request.options); });
    if (keys_.insert(tables::key_text(key)).second) tables_.push_back(std::move(request));
  }
};

/// Entries of a table baked at a fixed resolution; tables baked to an error target count as
/// larger than any (their size is chosen while baking).
std::uint64_t size_rank(const scene::TableRequest& r) {
  const auto* grid = std::get_if<tables::BakeOptions>(&r.options);
  return grid ? tables::table_bytes(grid->resolution) / tables::kBytesPerEntry : UINT64_MAX;
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  const std::optional<int> k = whole_int(std::string_view(text).substr(0, slash));
  const std::optional<int> n =
      slash == std::string::npos ? std::nullopt : whole_int(std::string_view(text).substr(slash + 1));
  if (!k || !n || *k < 0 || *n < 1 || *n > kMaxShards || *k >= *n)
    throw InputError("--shard '" + text + "' is not a shard; expected K/N with 0 <= K < N <= " +
                     std::to_string(kMaxShards) + " (e.g. 0/3, 1/3, 2/3)");
  return {*k, *n};
}

std::vector<scene::TableRequest> load_library(const std::string& path) { return LibraryParser(path).parse(); }

std::vector<scene::TableRequest> shard_of(const std::vector<scene::TableRequest>& tables, Shard shard) {
  std::vector<std::size_t> order(tables.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return size_rank(tables[a]) > size_rank(tables[b]); });
  std::vector<scene::TableRequest> out;
  for (std::size_t t = static_cast<std::size_t>(shard.index); t < order.size();
       t += static_cast<std::size_t>(shard.count))
    out.push_back(tables[order[t]]);
  return out;
}

}  // namespace ganzfeld::cli
