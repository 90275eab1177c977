// ganzfeld serve: the models, laws, tables and shaders over HTTP (serve/, docs/serve.md).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "serve/http.h"
#include "util/error.h"

namespace ganzfeld::cli {

namespace {
struct ServeArgs {
  std::string cache = "ganzfeld-cache";
  std::string data;
  serve::ServerOptions server;
  int jobs = 1, queue = 4;
  long long max_entries = serve::Limits{}.max_entries;
  long long max_evaluations = serve::Limits{}.max_evaluations;
  double max_request_seconds = serve::ServiceOptions{}.max_request_seconds;
  std::string allowed_hosts;
  long long max_connections = static_cast<long long>(serve::LoopOptions{}.max_connections);
};

/// `value` of flag `name` within [lo, hi], or a one-line InputError.
void check_range(const std::string& name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi))
    throw InputError(name + "=" + format_number(value) + " is out of range; allowed: " + format_number(lo) + " to " +
                     format_number(hi));
}

/// "a,b , c" -> {"a", "b", "c"}.
std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string item = text.substr(start, comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
    start = comma + 1;
  }
  return out;
}
}  // namespace

void add_serve_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("serve",
                                 "serve models, laws, tables (baked on demand into the cache) and shaders "
                                 "over HTTP until SIGINT/SIGTERM (docs/serve.md)");
  auto args = std::make_shared<ServeArgs>();
  const serve::LoopOptions loop;
  cmd->add_option("--cache", args->cache,
                  "the table cache directory, shared with `bake scene --out` (default ganzfeld-cache)");
  cmd->add_option("--data", args->data,
                  "a directory of measured data files (MERL, tabulated, Beard-Maxwell first-surface tables) served "
                  "by name: merl:file=NAME (default none: requests naming a file are refused)");
  cmd->add_option("--port", args->server.port, "TCP port (default 8080; 0: any free port, logged on stderr)");
  cmd->add_option("--bind", args->server.bind, "address to listen on (default 127.0.0.1: this machine only)");
  cmd->add_option("--allowed-hosts", args->allowed_hosts,
                  "comma-separated host names a request's Host may name besides localhost, 127.0.0.1, [::1] and "
                  "the --bind address ('*': any); others get 403");
  cmd->add_option("--jobs", args->jobs, "tables baked at once (default 1; each bake uses every core)");
  cmd->add_option("--queue", args->queue, "bakes waiting for a job (default 4); beyond them requests get 503");
  cmd->add_option("--connection-queue", args->server.waiting,
                  "requests waiting for a free connection thread (default " +
                      std::to_string(serve::ServerOptions{}.waiting) + "); beyond them a request gets 503");
  cmd->add_option("--max-connections", args->max_connections,
                  "connections open at once (default " + std::to_string(loop.max_connections) +
                      "); beyond them a connection gets 503");
  cmd->add_option("--max-entries", args->max_entries,
                  "largest table baked on demand, in entries (default " + std::to_string(serve::Limits{}.max_entries) +
                      "); larger requests get 413");
  cmd->add_option("--max-evaluations", args->max_evaluations,
                  "evaluation budget of one /api/eval and of each table entry (default " +
                      std::to_string(serve::Limits{}.max_evaluations) + "); beyond it: not converged");
  cmd->add_option("--max-request-seconds", args->max_request_seconds,
                  "wall-clock budget of one request's work and of one bake (default " +
                      format_number(serve::ServiceOptions{}.max_request_seconds) + "); beyond it: 503");
  cmd->add_option("--header-timeout", args->server.loop.header_seconds,
                  "seconds a request head may take from its first byte (default " + format_number(loop.header_seconds) +
                      "); beyond: 408 and closed");
  cmd->add_option(
      "--idle-timeout", args->server.loop.idle_seconds,
      "seconds a kept-alive connection waits for its next request (default " + format_number(loop.idle_seconds) + ")");
  cmd->add_option("--write-timeout", args->server.loop.write_seconds,
                  "seconds a client may take to read an answer (default " + format_number(loop.write_seconds) +
                      "); beyond: closed");
  cmd->add_option("--drain-seconds", args->server.drain_seconds,
                  "after SIGTERM, seconds to let running work finish before it is cancelled (default " +
                      format_number(serve::ServerOptions{}.drain_seconds) + ")");
  cmd->callback([&action, args] {
    action = [args] {
      if (args->server.port < 0 || args->server.port > 65535)
        throw InputError("--port=" + std::to_string(args->server.port) + " is out of range; allowed: 0 to 65535");
      if (args->jobs < 1 || args->jobs > 64)
        throw InputError("--jobs=" + std::to_string(args->jobs) + " is out of range; allowed: 1 to 64");
      if (args->queue < 0 || args->queue > 1024)
        throw InputError("--queue=" + std::to_string(args->queue) + " is out of range; allowed: 0 to 1024");
      if (args->server.waiting < 0 || args->server.waiting > 4096)
        throw InputError("--connection-queue=" + std::to_string(args->server.waiting) +
                         " is out of range; allowed: 0 to 4096");
      if (args->max_entries < 2)
        throw InputError("--max-entries=" + std::to_string(args->max_entries) + " is too small; allowed: >= 2");
      if (args->max_evaluations < 1000)
        throw InputError("--max-evaluations=" + std::to_string(args->max_evaluations) +
                         " is too small; allowed: >= 1000");
      check_range("--max-connections", static_cast<double>(args->max_connections), 1, 65536);
      check_range("--max-request-seconds", args->max_request_seconds, 0.1, 86400);
      check_range("--header-timeout", args->server.loop.header_seconds, 0.1, 3600);
      check_range("--idle-timeout", args->server.loop.idle_seconds, 0.1, 3600);
      check_range("--write-timeout", args->server.loop.write_seconds, 0.1, 3600);
      check_range("--drain-seconds", args->server.drain_seconds, 0, 60);
      serve::ServiceOptions options;
      if (!args->data.empty()) {
        options.data = serve::DataFiles::scan(args->data);
        std::fprintf(stderr, "ganzfeld serve: --data %s: %zu measured files served by name, %zu skipped\n",
                     args->data.c_str(), options.data.files().size(), options.data.skipped().size());
        for (const std::string& why : options.data.skipped()) std::fprintf(stderr, "  skipped %s\n", why.c_str());
      }
      options.cache_dir = prepare_directory("--cache", args->cache);
      options.jobs = args->jobs;
      options.queue = args->queue;
      options.limits.max_entries = static_cast<std::uint64_t>(args->max_entries);
      options.limits.max_evaluations = args->max_evaluations;
      options.max_request_seconds = args->max_request_seconds;
      options.command_line = shell_line;
      args->server.threads = std::max(32, 2 * (args->jobs + args->queue) + 8);
      args->server.allowed_hosts = comma_list(args->allowed_hosts);
      args->server.loop.max_connections = static_cast<std::size_t>(args->max_connections);
      args->server.loop.request_seconds = args->max_request_seconds;
      return serve::run(options, args->server);
    };
  });
}

}  // namespace ganzfeld::cli
