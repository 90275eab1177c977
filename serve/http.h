// The HTTP glue of `ganzfeld serve` (cpp-httplib, Debian libcpp-httplib-dev): every GET goes to
// Service::handle; one access-log line per request on stderr; SIGINT/SIGTERM stop the listener,
// discard queued bakes and let running ones finish (the cache never holds a partial file).
#pragma once

#include <string>

#include "serve/service.h"

namespace ganzfeld::serve {

struct ServerOptions {
  std::string bind = "127.0.0.1";  ///< localhost unless told otherwise
  int port = 8080;                 ///< 0: any free port (the log line says which)
  int threads = 16;                ///< connections served at once (some wait on bakes)
  int waiting = 64;                ///< connections accepted and waiting for a thread; beyond: 503 (connection_pool.h)
};

/// Serves until SIGINT or SIGTERM, then returns 0. Blocks those signals in every thread it
/// starts (the bake workers and the connection threads) and waits for them in one thread, so
/// call it before any other thread is started. Throws InputError when it cannot listen.
int run(const ServiceOptions& service, const ServerOptions& server);

}  // namespace ganzfeld::serve
