#include "serve/service.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>

#include "export/glsl.h"
#include "export/glsl_f.h"
#include "export/texture_file.h"
#include "models/registry.h"
#include "scene/plan.h"
#include "serve/assets.h"
#include "serve/etag.h"
#include "serve/field.h"
#include "shapes/json.h"
#include "tables/exr_io.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::serve {

namespace {

Reply json_reply(int status, const nlohmann::ordered_json& doc) {
  return {status, "application/json", doc.dump() + "\n", {}};
}

Reply error_reply(int status, const std::string& message) {
  return {status, "application/json", error_body(message), {}};
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read the cached table " + std::filesystem::path(path).filename().string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A table body in `format`; json: info --json (with the cache file name as path) + the values.
std::string table_body(const tables::CacheResult& r, TableFormat format, const std::string& file_name) {
  switch (format) {
    case TableFormat::exr: return file_bytes(r.path);
    case TableFormat::ktx2: {
      const std::vector<std::uint8_t> bytes = exporting::ktx2_bytes(r.table);
      return {bytes.begin(), bytes.end()};
    }
    case TableFormat::json: {
      nlohmann::ordered_json doc = shapes::info_json(file_name, r.table);
      doc["value"] = r.table.value;
      return doc.dump() + "\n";
    }
  }
  return {};
}

constexpr const char* kImmutable = "public, max-age=31536000, immutable";

/// `reply` with its strong ETag and Cache-Control: immutable (its request names one body
/// forever); 304 without a body when `if_none_match_header` matches.
Reply cacheable(Reply reply, const std::string& if_none_match_header) {
  const std::string etag = strong_etag(reply.body);
  reply.headers.insert(reply.headers.begin(), {{"ETag", etag}, {"Cache-Control", kImmutable}});
  if (!if_none_match_header.empty() && if_none_match(if_none_match_header, etag)) {
    reply.status = 304;  // RFC 9110, 15.4.5: no body, the same validators
    reply.body.clear();
  }
  return reply;
}

/// If-None-Match: * (RFC 9110, 13.1.2) asks for a body only when there is no representation at
/// all. A table's key names one body forever, so whatever the client holds is it: 304 without
/// reading or baking anything (and so without an ETag, which would need the body).
bool any_representation(const std::string& if_none_match_header) {
  const std::size_t first = if_none_match_header.find_first_not_of(" \t");
  const std::size_t last = if_none_match_header.find_last_not_of(" \t");
  return first != std::string::npos && if_none_match_header.substr(first, last - first + 1) == "*";
}

Reply unavailable(const std::string& message, bool retry) {
  Reply reply = error_reply(503, message);
  if (retry) reply.headers.emplace_back("Retry-After", std::to_string(kRetryAfterSeconds));
  return reply;
}

/// The answer to a request whose work stopped: 503, with Retry-After when retrying can help.
Reply stopped(const Cancellation* cancel, const std::string& message) {
  return unavailable(message, cancel && cancel->reason() == StopReason::shutdown);
}

/// Temporary files of util/atomic_file.h (".NAME.tmp-PID-N") in `dir` older than `seconds`:
/// left by a writer that was killed (kill -9) before its rename. Younger ones may belong to a
/// `bake` writing into the same cache now. Returns how many were removed.
int remove_stale_temporaries(const std::string& dir, double seconds) {
  namespace fs = std::filesystem;
  static const std::regex temporary(R"(\..+\.tmp-[0-9]+-[0-9]+)");
  int removed = 0;
  std::error_code ec;
  const auto now = fs::file_time_type::clock::now();
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec) || !std::regex_match(entry.path().filename().string(), temporary)) continue;
    const auto written = entry.last_write_time(ec);
    if (ec || std::chrono::duration<double>(now - written).count() <= seconds) continue;
    removed += fs::remove(entry.path(), ec) ? 1 : 0;
  }
  return removed;
}

}  // namespace

/// Held while a request computes or waits for a bake: at most max_computing at once.
class Service::ComputingSlot {
 public:
  explicit ComputingSlot(Service& service) : service_(service) {
    if (++service_.computing_ > service_.options_.max_computing) {
      --service_.computing_;
      ++service_.refused_computing_;
      throw Busy("all " + std::to_string(service_.options_.max_computing) +
                 " computing slots are taken (evaluations and bakes in progress); retry later");
    }
  }
  ~ComputingSlot() { --service_.computing_; }
  ComputingSlot(const ComputingSlot&) = delete;
  ComputingSlot& operator=(const ComputingSlot&) = delete;

 private:
  Service& service_;
};

std::string error_body(const std::string& message) { return nlohmann::json{{"error", message}}.dump() + "\n"; }

Service::Service(ServiceOptions options)
    : options_(std::move(options)),
      bakery_(options_.jobs, options_.queue, options_.max_request_seconds),
      models_(shapes::models_json().dump() + "\n") {
  if (const int removed = remove_stale_temporaries(options_.cache_dir, options_.max_request_seconds);
      removed && options_.log)
    options_.log("removed " + std::to_string(removed) + " temporary file(s) older than " +
                 format_number(options_.max_request_seconds) + " s from the cache (left by killed writers)");
}

void Service::drain() {
  draining_ = true;
  bakery_.drain();
}

void Service::cancel_running() { bakery_.cancel_running(); }

void Service::stop() {
  drain();
  bakery_.stop();
}

nlohmann::ordered_json Service::health() const {
  const Bakery::Stats s = bakery_.stats();
  nlohmann::ordered_json doc{{"status", draining_ ? "draining" : "ok"},
                             {"tables_baked", baked_.load()},
                             {"tables_reused", reused_.load()},
                             {"bakes_joined", s.joined},
                             {"bakes_refused", s.refused},
                             {"bakes_cancelled", s.cancelled},
                             {"bakes_running", s.running},
                             {"bakes_queued", s.queued},
                             {"jobs", options_.jobs},
                             {"queue", options_.queue},
                             {"requests_computing", computing_.load()},
                             {"computing_refused", refused_computing_.load()},
                             {"max_computing", options_.max_computing}};
  if (options_.connection_stats) doc.update(options_.connection_stats());
  return doc;
}

Reply Service::handle(const std::string& path, std::string_view query, const std::string& if_none_match,
                      const Cancellation* cancel) {
  try {
    return handle(Request{path, parse_query(query), if_none_match, cancel});
  } catch (const RequestError& e) { return error_reply(e.status(), e.what()); }
}

std::string Service::without_paths(std::string message) const {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> prefixes{options_.cache_dir, fs::absolute(options_.cache_dir, ec).string(),
                                    fs::weakly_canonical(options_.cache_dir, ec).string()};
  std::sort(prefixes.begin(), prefixes.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (const std::string& prefix : prefixes) {
    if (prefix.empty()) continue;
    for (const std::string& form : {prefix + "/", prefix})
      for (std::size_t at; (at = message.find(form)) != std::string::npos;) message.replace(at, form.size(), "");
  }
  return message;
}

Reply Service::handle(const Request& request) {
  try {
    const std::string& path = request.path;
    const Query& query = request.query;
    // The viewer's files (serve/assets.h); the page reads its own query (model, light, test mode).
    if (const Asset* asset = find_asset(path))
      return {200, std::string(asset->media_type), std::string(asset->body), {}};
    const bool fixed = path == "/healthz" || path == "/api/models" || path == "/api/data";
    if (fixed && !query.empty()) return error_reply(400, path + " takes no parameters");
    if (path == "/healthz") return json_reply(draining_ ? 503 : 200, health());
    if (path == "/api/models") return {200, "application/json", models_, {}};
    if (path == "/api/data") return json_reply(200, options_.data.listing());
    if (path == "/api/eval") return eval(request);
    if (path == "/api/spec") {
      const SpecQuery q = parse_spec_query(query, options_.limits, options_.data);
      return json_reply(200, shapes::spec_json(q.spec, options_.data.display(q.model->spec())));
    }
    if (path == "/api/fgrid") {
      const FGridQuery q = parse_fgrid(query, options_.data);
      return cacheable(json_reply(200, fgrid_json(q, options_.data)), request.if_none_match);
    }
    if (path == "/api/sphere") return sphere(request);
    if (path == "/api/table") return table(request, TableEndpoint::table);
    if (path == "/api/glsl") {
      if (query.count("scene")) return scene_glsl(request);
      return is_f_glsl(query) ? f_shader(request) : table(request, TableEndpoint::glsl);
    }
    return error_reply(404, "no endpoint '" + path +
                                "'; allowed: /, /viewer.js, /healthz, /api/models, /api/data, /api/spec, /api/eval, "
                                "/api/fgrid, /api/sphere, /api/table, /api/glsl");
  } catch (const RequestError& e) { return error_reply(e.status(), e.what()); } catch (const Busy& e) {
    return unavailable(e.what(), true);
  } catch (const Cancelled& e) { return stopped(request.cancel, e.what()); } catch (const InputError& e) {
    return error_reply(400, without_paths(e.worded(InputError::query_spelling)));
  } catch (const std::exception& e) {
    if (options_.log) options_.log("internal error on " + request.path + ": " + e.what());
    return error_reply(500, "internal error: " + without_paths(e.what()));
  }
}

Reply Service::eval(const Request& request) {
  const EvalQuery q = parse_eval(request.query, options_.limits, options_.data);
  const ComputingSlot slot(*this);
  CubatureOptions options = q.options;
  if (request.cancel) options.cancel = request.cancel->flag();
  const util::Stopwatch watch;
  const Estimate e = evaluate_law(*q.model, q.law, q.i.value_or(Vec3{0, 0, 1}), q.j.value_or(Vec3{0, 0, 1}), options);
  if (request.cancel && request.cancel->cancelled())
    return stopped(request.cancel, stop_message(request.cancel->reason(), options_.max_request_seconds));
  return json_reply(
      200, shapes::eval_json(options_.data.display(q.model->spec()), q.law, e, q.tolerance, q.i, q.j, watch.seconds()));
}

std::optional<tables::Table> Service::cached(const TableQuery& q, const std::string& path) {
  std::string why;
  std::optional<tables::Table> table =
      tables::read_if_matching(path, tables::table_key(*q.model, q.law, q.options), &why);
  if (!why.empty() && options_.log)
    options_.log("cache entry " + q.file_name + " refused (" + why + "); baking it again");
  return table;
}

Bakery::Result Service::obtain(const TableQuery& q, std::string& status, const Cancellation* cancel) {
  const std::string path = (std::filesystem::path(options_.cache_dir) / q.file_name).string();
  if (std::optional<tables::Table> table = cached(q, path)) {
    ++reused_;
    status = "reused";
    return std::make_shared<const tables::CacheResult>(
        tables::CacheResult{path, tables::CacheStatus::reused, std::move(*table), 0.0});
  }
  const ComputingSlot slot(*this);
  const Bakery::Ticket ticket = bakery_.submit(q.key, [this, q, path](const std::atomic<bool>& stop) {
    scene::TableRequest request{q.model->spec(), q.law, q.model, q.options};
    const std::string command = options_.command_line ? options_.command_line(scene::bake_command(request, path)) : "";
    tables::BakeRequest options = q.options;
    tables::common(options).cancel = &stop;
    tables::CacheResult baked;
    try {
      baked = tables::bake_or_reuse(path, *q.model, q.law, options, command);
    } catch (const InputError& e) {
      // A refusal naming a parameter (a max_error no scheme reaches) is the client's; the cache not
      // taking the file (a directory at its name, a full disk) is ours.
      if (!e.refused().parameter.empty()) throw RequestError(400, e.worded(InputError::query_spelling));
      throw std::runtime_error("the cache cannot hold " + q.file_name + ": " + e.what());
    }
    auto r = std::make_shared<const tables::CacheResult>(std::move(baked));
    ++(r->status == tables::CacheStatus::baked ? baked_ : reused_);
    return r;
  });
  Bakery::Result result = bakery_.wait(ticket, cancel);
  status = ticket.joined ? "joined" : tables::to_string(result->status);
  return result;
}

Reply Service::sphere(const Request& request) {
  const SphereQuery q = parse_sphere(request.query, options_.data);
  if (q.law == Law::f) return cacheable(json_reply(200, sphere_json(q, options_.data)), request.if_none_match);
  const ComputingSlot slot(*this);  // g and h: a cubature per pixel, as /api/eval's
  return cacheable(json_reply(200, sphere_json(q, options_.data)), request.if_none_match);
}

Reply Service::f_shader(const Request& request) {
  const ModelPtr model = parse_f_glsl(request.query, options_.limits, options_.data);
  return cacheable({200, "text/plain; charset=utf-8", exporting::glsl_model_f(*model), {}}, request.if_none_match);
}

Reply Service::table(const Request& request, TableEndpoint endpoint) {
  const TableQuery q = parse_table(request.query, options_.limits, endpoint, options_.defaults, options_.data);
  if (any_representation(request.if_none_match)) return {304, "application/json", "", {{"Cache-Control", kImmutable}}};
  std::string status;
  const Bakery::Result r = obtain(q, status, request.cancel);
  Reply reply;
  if (endpoint == TableEndpoint::glsl) {
    reply.content_type = "text/plain; charset=utf-8";
    reply.body = exporting::glsl_table_snippet(r->table);
  } else {
    reply.content_type = content_type(q.format);
    reply.body = table_body(*r, q.format, q.file_name);
  }
  reply.headers = {{"X-Ganzfeld-Table", status}};
  return cacheable(std::move(reply), request.if_none_match);
}

Reply Service::scene_glsl(const Request& request) {
  const SceneQuery q = parse_scene_glsl(request.query);
  if (any_representation(request.if_none_match)) return {304, "application/json", "", {{"Cache-Control", kImmutable}}};
  const std::size_t needed = scene::tables_needed(q.scene, options_.defaults).size();
  if (needed > options_.limits.max_scene_tables)
    throw RequestError(413, "the scene needs " + std::to_string(needed) + " tables; this service bakes at most " +
                                std::to_string(options_.limits.max_scene_tables) +
                                " for one scene (use `ganzfeld "
                                "export-glsl --scene`)");
  scene::TableStore store;
  std::string statuses;  // "baked", "reused", "joined" of each table, comma-separated
  store.obtain = [&](scene::TableRequest r) {
    std::string status;
    tables::common(r.options).max_evaluations = options_.limits.max_evaluations;
    const Bakery::Result result = obtain(table_query(r.model, r.law, r.options), status, request.cancel);
    statuses += (statuses.empty() ? "" : ",") + status;
    scene::PlannedTable planned{std::move(r), std::shared_ptr<const tables::Table>(result, &result->table),
                                result->path, result->status, result->seconds};
    return planned;
  };
  const scene::ShadingPlan plan = scene::plan_shading(q.scene, options_.defaults, store);
  Reply reply;
  reply.body = exporting::glsl_scene_shader(q.scene, plan, kSceneShaderSource);
  reply.content_type = "text/plain; charset=utf-8";
  if (q.json) {
    nlohmann::ordered_json textures = nlohmann::ordered_json::array();
    for (const scene::PlannedTable& t : plan.tables)
      textures.push_back({{"sampler", exporting::glsl_sampler_name(t.request.spec, t.request.law)},
                          {"type", exporting::glsl_sampler_type(t.request.law)},
                          {"model", t.request.spec},
                          {"law", to_string(t.request.law)},
                          {"file", std::filesystem::path(t.path).filename().string()}});
    reply.body = nlohmann::ordered_json{{"glsl", reply.body}, {"textures", textures}}.dump() + "\n";
    reply.content_type = "application/json";
  }
  reply.headers = {{"X-Ganzfeld-Table", statuses.empty() ? "none" : statuses}};
  return cacheable(std::move(reply), request.if_none_match);
}

}  // namespace ganzfeld::serve
