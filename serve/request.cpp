#include "serve/request.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "export/glsl.h"
#include "models/mixture.h"
#include "models/registry.h"
#include "models/spec.h"
#include "tables/cache.h"
#include "tables/to_error.h"
#include "util/error.h"

namespace ganzfeld::serve {

namespace {

RequestError bad(const std::string& message) { return RequestError(400, message); }

double angle(const Query& query, const std::string& name, double max_deg, const std::string& why) {
  const std::optional<double> deg = number(query, name);
  if (!deg) throw bad("missing parameter '" + name + "'" + why);
  if (*deg < 0.0 || *deg > max_deg)
    throw bad(name + "=" + format_number(*deg) + " is out of range; allowed: [0, " + format_number(max_deg) +
              "] degrees");
  return *deg * std::numbers::pi / 180.0;
}

double tolerance(const Query& query, double fallback) {
  const double tol = number(query, "tol").value_or(fallback);
  if (tol < 1e-15 || tol > 1.0)
    throw bad("tol=" + format_number(tol) + " is not allowed; expected an absolute tolerance in [1e-15, 1]");
  return tol;
}

/// Library refusals (InputError) become 400, their parameters named as a query names them.
template <class F>
auto as_request(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) { throw bad(e.worded(InputError::query_spelling)); }
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string decoded(std::string_view text) {
  std::string out;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '+') {
      out += ' ';
    } else if (text[k] != '%') {
      out += text[k];
    } else {
      const int hi = k + 2 < text.size() ? hex_digit(text[k + 1]) : -1;
      const int lo = hi >= 0 ? hex_digit(text[k + 2]) : -1;
      if (lo < 0) throw bad("malformed query: '" + std::string(text) + "' has a '%' not followed by two hex digits");
      out += static_cast<char>(hi * 16 + lo);
      k += 2;
    }
  }
  return out;
}

}  // namespace

void check_names(const Query& query, const std::string& endpoint, const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& name : allowed) list += (list.empty() ? "" : ", ") + name;
  for (auto it = query.begin(); it != query.end(); it = query.upper_bound(it->first)) {
    if (std::find(allowed.begin(), allowed.end(), it->first) == allowed.end())
      throw bad("unknown parameter '" + it->first + "' for " + endpoint + "; allowed: " + list);
    if (query.count(it->first) > 1) throw bad("parameter '" + it->first + "' is given more than once");
  }
}

std::optional<std::string> text_of(const Query& query, const std::string& name) {
  const auto it = query.find(name);
  if (it == query.end()) return std::nullopt;
  return it->second;
}

std::string required(const Query& query, const std::string& name, const std::string& example) {
  const std::optional<std::string> text = text_of(query, name);
  if (!text || text->empty()) throw bad("missing parameter '" + name + "'; e.g. " + name + "=" + example);
  return *text;
}

std::optional<double> number(const Query& query, const std::string& name) {
  const std::optional<std::string> text = text_of(query, name);
  if (!text) return std::nullopt;
  double x = 0.0;
  const char* const last = text->data() + text->size();
  const auto [end, status] = std::from_chars(text->data(), last, x, std::chars_format::general);
  if (text->empty() || status != std::errc() || end != last || !std::isfinite(x))
    throw bad(name + "='" + *text + "' is not a number; expected a finite decimal number such as 45, 0.5 or 1e-9");
  return x;
}

Query parse_query(std::string_view text) {
  Query query;
  while (!text.empty()) {
    const std::size_t amp = text.find('&');
    const std::string_view pair = text.substr(0, amp);
    if (!pair.empty()) {
      const std::size_t eq = pair.find('=');
      query.emplace(decoded(pair.substr(0, eq)), eq == std::string_view::npos ? "" : decoded(pair.substr(eq + 1)));
    }
    if (amp == std::string_view::npos) break;
    text.remove_prefix(amp + 1);
  }
  return query;
}

namespace {
/// Refuses (400) a parsed spec with a data file item (file=PATH); nothing has read it yet.
void refuse_data_file(const Spec& spec, const std::string& text) {
  if (spec.names_file())
    throw bad("model '" + text +
              "' names a data file; the service reads no file outside its cache: allowed: "
              "analytic models and mixtures (see /api/models)");
}

/// refuse_data_file of every string in a JSON document that parses as a spec (as decoded:
/// escapes cannot hide one). A string that does not parse is no model the scene parser builds.
void refuse_data_files(const nlohmann::json& value) {
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    std::optional<Spec> spec;
    try {
      spec = parse_spec(text);
    } catch (const InputError&) {}
    if (spec) refuse_data_file(*spec, text);
  }
  if (value.is_structured())
    for (const auto& item : value) refuse_data_files(item);
}
}  // namespace

SpecQuery parse_served_spec(const std::string& text, const Limits& limits, const DataFiles& data) {
  const Spec parsed = as_request([&] { return parse_spec(text); });
  if (!data.enabled()) refuse_data_file(parsed, text);
  const Spec spec = data.resolve(parsed);
  if (spec.terms.size() > limits.max_lobes)
    throw RequestError(413, "model '" + text.substr(0, 80) + (text.size() > 80 ? "...'" : "'") + " is a mixture of " +
                                std::to_string(spec.terms.size()) + " lobes; this service computes at most " +
                                std::to_string(limits.max_lobes) + " (use `ganzfeld eval` or `ganzfeld bake`)");
  return {spec, as_request([&] { return make_model(spec); })};
}

ModelPtr parse_served_model(const std::string& spec, const Limits& limits, const DataFiles& data) {
  return parse_served_spec(spec, limits, data).model;
}

SpecQuery parse_spec_query(const Query& query, const Limits& limits, const DataFiles& data) {
  check_names(query, "/api/spec", {"model"});
  return parse_served_spec(required(query, "model", "specular:alpha=8"), limits, data);
}

EvalQuery parse_eval(const Query& query, const Limits& limits, const DataFiles& data) {
  check_names(query, "/api/eval", {"model", "law", "theta_i", "theta_j", "phi", "tol"});
  EvalQuery q;
  q.law = as_request([&] { return parse_law(required(query, "law", "g (one of f, g, h, a, r)")); });
  q.model = parse_served_model(required(query, "model", "specular:alpha=8"), limits, data);
  const bool needs_i = q.law == Law::f || q.law == Law::g || q.law == Law::a;
  const bool needs_j = q.law == Law::f || q.law == Law::g || q.law == Law::h;
  const std::string law = std::string(" (law ") + to_string(q.law) + " needs it)";
  if (needs_i) q.i = direction(angle(query, "theta_i", q.law == Law::g ? 180.0 : 90.0, law), 0.0);
  const double phi = number(query, "phi").value_or(0.0);
  if (std::abs(phi) > kMaxPhi)
    throw bad("phi=" + format_number(phi) + " is out of range; allowed: [-" + format_number(kMaxPhi) + ", " +
              format_number(kMaxPhi) + "] degrees");
  if (needs_j) q.j = direction(angle(query, "theta_j", 90.0, law), phi * std::numbers::pi / 180.0);
  q.tolerance = tolerance(query, 1e-9);
  q.options.abs_tol = q.tolerance;
  q.options.max_evaluations = limits.max_evaluations;
  return q;
}

bool is_f_glsl(const Query& query) {
  const auto law = query.find("law");
  return law != query.end() && law->second == "f";
}

ModelPtr parse_f_glsl(const Query& query, const Limits& limits, const DataFiles& data) {
  check_names(query, "/api/glsl with law=f", {"model", "law"});
  return parse_served_model(required(query, "model", "specular:alpha=8"), limits, data);
}

namespace {
/// Every table format the service answers in: its query name and its Content-Type.
struct FormatInfo {
  TableFormat format;
  const char* name;
  const char* content_type;
};
constexpr FormatInfo kFormats[] = {{TableFormat::exr, "exr", "image/x-exr"},
                                   {TableFormat::ktx2, "ktx2", "image/ktx2"},
                                   {TableFormat::json, "json", "application/json"}};
const FormatInfo& info(TableFormat format) {
  for (const FormatInfo& f : kFormats)
    if (f.format == format) return f;
  return kFormats[0];  // unreachable: kFormats lists every enumerator
}
}  // namespace

const char* to_string(TableFormat format) { return info(format).name; }
const char* content_type(TableFormat format) { return info(format).content_type; }

TableQuery parse_table(const Query& query, const Limits& limits, TableEndpoint endpoint,
                       const scene::TableOptions& defaults, const DataFiles& data) {
  std::vector<std::string> names{"model", "law", "res", "tol", "encoding", "max_error", "fetches"};
  if (endpoint == TableEndpoint::table) names.push_back("format");
  check_names(query, endpoint == TableEndpoint::table ? "/api/table" : "/api/glsl", names);
  if (query.count("max_error") && (query.count("res") || query.count("tol")))
    throw bad(std::string("give ") + (query.count("res") ? "res" : "tol") +
              " or max_error, not both: with max_error the baker chooses the resolution and the tolerance");
  TableQuery q;
  q.law = as_request([&] { return tables::parse_tabulated_law("law", required(query, "law", "g (one of g, h, a)")); });
  q.model = parse_served_model(required(query, "model", "specular:alpha=8"), limits, data);
  if (!q.model->traits().isotropic)
    throw bad("model '" + q.model->spec() + "' is anisotropic; tables hold isotropic models only");
  const tables::Encoding encoding =
      text_of(query, "encoding") ? as_request([&] { return tables::parse_encoding(*text_of(query, "encoding")); })
                                 : defaults.encoding;
  const Law grid_law = q.law == Law::g ? Law::g : Law::h;  // a: h's grid
  if (const auto max_error = number(query, "max_error")) {
    // As `bake model --max-error`: the smallest table whose validated lookup error is <= max_error,
    // within this service's own size cap (max_entries floats of values).
    tables::TargetBake bake;
    bake.target.lookup_error = *max_error;
    bake.target.max_bytes = limits.max_entries * sizeof(float);
    bake.target.max_fetches = scene::kSceneSearchFetches;  // as a scene's --max-error without --fetches
    bake.target.best_effort = false;                       // a target asked for is met or refused
    q.options = bake;
  } else if (defaults.target && !query.count("res") && !query.count("tol")) {
    q.options = defaults.request(grid_law);  // the defaults' target (the scene defaults: best effort)
    if (auto* bake = std::get_if<tables::TargetBake>(&q.options)) {  // within the service's size cap too
      const std::uint64_t cap = limits.max_entries * sizeof(float);
      std::uint64_t& bytes = bake->target.max_bytes;  // 0: the baker's default cap
      bytes = bytes == 0 ? cap : std::min(bytes, cap);
    }
  } else {  // res or tol, as the command line's --res/--tol: a fixed grid, no search
    tables::BakeOptions grid;
    grid.resolution = grid_law == Law::g ? defaults.resolution_g : defaults.resolution_h;
    if (const auto res = text_of(query, "res"))
      grid.resolution = as_request([&] { return tables::parse_resolution(*res, q.law); });
    const std::uint64_t entries = tables::table_bytes(grid.resolution) / tables::kBytesPerEntry;
    if (entries > limits.max_entries)
      throw RequestError(413, "res=" + tables::resolution_text(grid.resolution) + " is " + std::to_string(entries) +
                                  " entries; this service bakes at most " + std::to_string(limits.max_entries) +
                                  " on demand (bake larger tables with `ganzfeld bake model`)");
    grid.tolerance = tolerance(query, defaults.tolerance);
    q.options = grid;
  }
  if (const auto fetches = number(query, "fetches")) {  // as `bake model --fetches N`: the lookup's fetch budget
    tables::TargetBake* bake = std::get_if<tables::TargetBake>(&q.options);
    if (!bake) throw bad(tables::needs_target("fetches").what());
    if (*fetches != std::floor(*fetches) || *fetches < 1 || *fetches > 1e6)
      throw bad("fetches=" + format_number(*fetches) + " is not allowed; expected an integer >= 1");
    bake->target.max_fetches = static_cast<int>(*fetches);
  }
  tables::BakeCommon& common = tables::common(q.options);
  common.max_evaluations = limits.max_evaluations;
  common.encoding = encoding;
  if (const auto format = text_of(query, "format")) {
    const auto known =
        std::find_if(std::begin(kFormats), std::end(kFormats), [&](const FormatInfo& f) { return *format == f.name; });
    if (known == std::end(kFormats)) throw bad("unknown format '" + *format + "'; allowed: exr, ktx2, json");
    q.format = known->format;
  }
  return table_query(q.model, q.law, q.options, q.format);
}

TableQuery table_query(ModelPtr model, Law law, tables::BakeRequest options, TableFormat format) {
  TableQuery q{std::move(model), law, std::move(options), format, "", ""};
  const tables::TableKey key = as_request([&] { return tables::table_key(*q.model, q.law, q.options); });
  q.key = tables::key_text(key);
  q.file_name = tables::cache_file_name(key);
  return q;
}

SceneQuery parse_scene_glsl(const Query& query) {
  check_names(query, "/api/glsl with scene", {"scene", "format"});
  const std::string text = required(query, "scene", "{...}");
  // The scene parser reads a model's data file while it parses the spec (and its messages
  // describe the bytes): every string is checked first. Malformed JSON is left to the parser's
  // message.
  refuse_data_files(nlohmann::json::parse(text, nullptr, false));
  SceneQuery q{as_request([&] { return load_scene_text(text, "scene"); }), false};
  as_request([&] {
    exporting::check_scene_exportable(q.scene);
    return 0;
  });
  const std::string format = text_of(query, "format").value_or("glsl");
  if (format != "glsl" && format != "json") throw bad("unknown format '" + format + "'; allowed: glsl, json");
  q.json = format == "json";
  return q;
}

}  // namespace ganzfeld::serve
