// ganzfeld serve: the models, laws, tables and shaders over HTTP (serve/, docs/serve.md).
#include <algorithm>
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
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
};
}  // namespace

void add_serve_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("serve", "serve models, laws, tables (baked on demand into the cache) and shaders "
                                          "over HTTP until SIGINT/SIGTERM (docs/serve.md)");
  auto args = std::make_shared<ServeArgs>();
  cmd->add_option("--cache", args->cache, "the table cache directory, shared with `bake --scene --out` (default ganzfeld-cache)");
  cmd->add_option("--data", args->data,
                  "a directory of measured data files (MERL, tabulated, Beard-Maxwell first-surface tables) served "
                  "by name: merl:file=NAME (default none: requests naming a file are refused)");
  cmd->add_option("--port", args->server.port, "TCP port (default 8080; 0: any free port, logged on stderr)");
  cmd->add_option("--bind", args->server.bind, "address to listen on (default 127.0.0.1: this machine only)");
  cmd->add_option("--jobs", args->jobs, "tables baked at once (default 1; each bake uses every core)");
  cmd->add_option("--queue", args->queue, "bakes waiting for a job (default 4); beyond them requests get 503");
  cmd->add_option("--connection-queue", args->server.waiting,
                  "connections waiting for a free connection thread (default " +
                      std::to_string(serve::ServerOptions{}.waiting) + "); beyond them a connection gets 503");
  cmd->add_option("--max-entries", args->max_entries,
                  "largest table baked on demand, in entries (default " + std::to_string(serve::Limits{}.max_entries) +
                      "); larger requests get 413");
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
      options.command_line = shell_line;
      args->server.threads = std::max(16, 2 * (args->jobs + args->queue) + 4);
      return serve::run(options, args->server);
    };
  });
}

}  // namespace ganzfeld::cli
