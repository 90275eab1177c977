// The HTTP side of `ganzfeld serve`: the sockets are the connection loop's (serve/connection_loop.h),
// the answers the workers' (serve/worker_pool.h), each request head parsed and routed by
// cpp-httplib (Debian libcpp-httplib-dev; this is the only file that sees it) into Service::handle.
// One access-log line per request on stderr. SIGINT/SIGTERM drain: /healthz says "draining",
// new bakes are refused, what is in flight may finish for `drain_seconds`, then every request and
// bake still running is cancelled (the cache never holds a partial file) and the process exits.
#pragma once

#include <string>
#include <vector>

#include "serve/connection_loop.h"
#include "serve/service.h"

namespace ganzfeld::serve {

struct ServerOptions {
  std::string bind = "127.0.0.1";  ///< localhost unless told otherwise
  int port = 8080;                 ///< 0: any free port (the log line says which)
  int threads = 32;                ///< requests answered at once (some compute or wait on bakes)
  int waiting = 64;                ///< requests waiting for a thread; beyond: 503
  /// Host names (without port) a request's Host may name, besides localhost, 127.0.0.1, [::1] and
  /// the bound address; "*" allows any. Others: 403 (a page elsewhere reaching this service
  /// through DNS rebinding).
  std::vector<std::string> allowed_hosts;
  LoopOptions loop;            ///< connections, deadlines, head size
  double drain_seconds = 1.0;  ///< after SIGTERM, before what still runs is cancelled
};

/// Serves until SIGINT or SIGTERM, then returns 0. Blocks those signals in every thread it
/// starts (the bake workers, the connection loop, the workers) and waits for them in the calling
/// thread, so call it before any other thread is started. Throws InputError when it cannot listen.
int run(const ServiceOptions& service, const ServerOptions& server);

/// Whether a Host header value is one `allowed` names (host part only, case-insensitive;
/// "*" in `allowed` allows any). An empty value is not allowed.
bool host_allowed(const std::string& host_header, const std::vector<std::string>& allowed);

}  // namespace ganzfeld::serve
