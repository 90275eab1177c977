// `ganzfeld serve` without HTTP (docs/serve.md): a request (path, decoded query, If-None-Match)
// becomes a reply (status, media type, body, headers). The httplib glue (serve/http.h) only
// moves bytes; everything that decides an answer is here and unit-tested (tests/serve_test.cpp).
//
//   GET /, /viewer.js the viewer (serve/viewer/, embedded: serve/assets.h)
//   GET /healthz      {"status": "ok", bakes and queue counters}
//   GET /api/models   shapes::models_json (= `ganzfeld models --json`)
//   GET /api/eval     shapes::eval_json   (= `ganzfeld eval --json`)
//   GET /api/table    the table from the cache (baked on demand: serve/bakery.h) as exr, ktx2 or json
//   GET /api/glsl     export::glsl_table_snippet of that table; with law=f, export::glsl_model_f;
//                     with scene=SCENE the scene's shader (export::glsl_scene_shader) and its tables
//   GET /api/data     the measured files of --data DIR, by name (serve/data.h)
//   GET /api/fgrid    f over a direction grid; GET /api/sphere the figure's sphere (serve/field.h)
// Errors: {"error": "one line"} with 400 (bad value), 404 (no such endpoint), 413 (too large),
// 503 (no bake or computing slot free, or shutting down: Retry-After; or the request's work was
// stopped: its deadline, its client gone: serve/cancellation.h) or 500.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/plan.h"
#include "serve/bakery.h"
#include "serve/cancellation.h"
#include "serve/request.h"

namespace ganzfeld::serve {

struct ServiceOptions {
  std::string cache_dir;  ///< the table cache (already created); the only files the service reads
  int jobs = 1;           ///< bakes at once
  int queue = 4;          ///< bakes waiting; beyond: 503
  /// Wall-clock budget of a bake (the connection loop gives each request the same): beyond it
  /// the bake is cancelled and its requests get 503. Also the age beyond which a temporary file
  /// in the cache is a writer's leftover (removed at start).
  double max_request_seconds = 60.0;
  /// Requests computing (/api/eval) or waiting for a bake at once; beyond: 503, so that some
  /// connection threads always remain for cheap requests (cached tables, /healthz, the viewer).
  int max_computing = 28;
  Limits limits;
  scene::TableOptions defaults = scene::TableOptions::scene_defaults();  ///< what unset table parameters mean
  DataFiles data;  ///< `--data DIR`: the measured files requests may name (serve/data.h)
  /// Joins the words of the equivalent `ganzfeld bake` into the line stamped into each table.
  std::function<std::string(const std::vector<std::string>&)> command_line;
  /// One line for the operator's log (cache entries refused and baked again, internal errors
  /// with their paths, temporary files removed); nothing when empty.
  std::function<void(const std::string&)> log;
  /// More fields for /healthz (the connection loop's counters); nothing when empty.
  std::function<nlohmann::ordered_json()> connection_stats;
};

struct Request {
  std::string path;           ///< decoded, without the query
  Query query;                ///< decoded
  std::string if_none_match;  ///< the header, or empty
  /// Set when the request's work should stop (serve/cancellation.h); none: never.
  const Cancellation* cancel = nullptr;
};

struct Reply {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

/// Seconds a client is told to wait after a 503.
inline constexpr int kRetryAfterSeconds = 2;

/// What a served scene shader's header comment names as its source.
inline constexpr const char* kSceneShaderSource = "the scene of a GET /api/glsl request";

class Service {
 public:
  explicit Service(ServiceOptions options);

  /// The reply to `request`; never throws.
  Reply handle(const Request& request);
  /// handle() of a path (decoded), a raw query (parse_query) and an If-None-Match header.
  Reply handle(const std::string& path, std::string_view query, const std::string& if_none_match,
               const Cancellation* cancel = nullptr);

  /// Shutting down: refuses new bakes, discards queued ones; /healthz answers 503 "draining".
  void drain();
  /// Cancels the running bakes (their requests get 503).
  void cancel_running();
  /// drain(), then waits for the bake workers (serve/bakery.h).
  void stop();

  /// {"status": "ok" or "draining", counters: tables baked (written), reused (read from the
  /// cache), bakes joined, refused, cancelled, requests computing, ...}.
  nlohmann::ordered_json health() const;

 private:
  Reply eval(const Request& request);
  Reply table(const Request& request, TableEndpoint endpoint);
  /// GET /api/glsl?scene=...: the scene's shader, its tables obtained through the bakery.
  Reply scene_glsl(const Request& request);
  Reply f_shader(const Request& request);
  /// The table of `q` from the cache, or baked (single flight); `status`: baked, reused or joined.
  Bakery::Result obtain(const TableQuery& q, std::string& status, const Cancellation* cancel);
  /// The table of `q` if the cache holds it verified; logs why a file there was refused.
  std::optional<tables::Table> cached(const TableQuery& q, const std::string& path);
  /// One of max_computing slots for the caller's scope, or Busy.
  class ComputingSlot;
  /// `message` without the cache directory's path (error bodies name files by their cache name).
  std::string without_paths(std::string message) const;
  /// GET /api/sphere: f at once, g and h (a cubature per pixel) in a computing slot.
  Reply sphere(const Request& request);

  ServiceOptions options_;
  Bakery bakery_;
  std::string models_;  ///< the registry never changes while serving
  std::atomic<long long> baked_{0}, reused_{0}, refused_computing_{0};
  std::atomic<int> computing_{0};
  std::atomic<bool> draining_{false};
};

/// {"error": message} as one line of JSON.
std::string error_body(const std::string& message);

}  // namespace ganzfeld::serve
