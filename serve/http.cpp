#include "serve/http.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <pthread.h>
#include <sys/socket.h>
#include <thread>

#include <httplib.h>

#include "serve/connection_pool.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::serve {

namespace {

std::mutex log_mutex;

/// Connections the kernel holds for the listener before it accepts them. cpp-httplib 0.11
/// listens with CPPHTTPLIB_LISTEN_BACKLOG = 5, compiled into Debian's library: a burst of more
/// connections (16 load-test clients, a browser's parallel requests) loses SYNs, and each lost
/// one costs its client a 1 s retransmission (RFC 6298 2.1), seen as 1 s and 2 s maxima in
/// docs/serve-load.md before this. Still bounded: the kernel caps it at net.core.somaxconn.
constexpr int kListenBacklog = 128;

/// One line on stderr: "ganzfeld serve: MESSAGE".
void log_line(const std::string& message) {
  std::lock_guard lock(log_mutex);
  std::fprintf(stderr, "ganzfeld serve: %s\n", message.c_str());
  std::fflush(stderr);
}

}  // namespace

int run(const ServiceOptions& service_options, const ServerOptions& options) {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // inherited by every thread started below

  Service service(service_options);
  httplib::Server server;
  const auto threads = static_cast<std::size_t>(options.threads), waiting = static_cast<std::size_t>(options.waiting);
  server.new_task_queue = [threads, waiting] { return new ConnectionPool(threads, waiting); };
  server.set_payload_max_length(64 * 1024);  // GET only: a larger body gets 413
  server.set_keep_alive_timeout(5);
  // Without TCP_NODELAY, a keep-alive client waits ~40 ms for each answer: the headers and the
  // body leave in two writes, and Nagle holds the second until the client's delayed ACK of the
  // first (RFC 896, RFC 1122 4.2.3.2). Measured by scripts/gen-serve-load-docs.
  server.set_tcp_nodelay(true);
  server.Get(".*", [&service, &options](const httplib::Request& req, httplib::Response& res) {
    if (ConnectionPool::shedding()) {  // every connection thread busy, the connection queue full
      res.status = 503;
      res.set_header("Retry-After", std::to_string(kRetryAfterSeconds));
      res.set_header("Connection", "close");
      res.set_content(error_body("all " + std::to_string(options.threads) + " connection threads are busy and " +
                                 std::to_string(options.waiting) + " connections wait; retry later"),
                      "application/json");
      return;
    }
    const util::Stopwatch watch;
    const std::size_t mark = req.target.find('?');
    const std::string query = mark == std::string::npos ? "" : req.target.substr(mark + 1);
    const Reply reply = service.handle(req.path, query, req.get_header_value("If-None-Match"));
    res.status = reply.status;
    for (const auto& [name, value] : reply.headers) res.set_header(name, value);
    res.set_header("Server-Timing", "total;dur=" + std::to_string(watch.seconds() * 1000.0));
    if (reply.status != 304) res.set_content(reply.body, reply.content_type);
  });
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string message = res.status == 413   ? "request too large; GET requests carry no body"
                                : res.status == 414 ? "request URI too long"
                                : res.status == 404 || res.status == 405
                                    ? "only GET (and HEAD) requests are served"
                                    : "bad request";
    res.set_content(error_body(message), "application/json");
  });
  server.set_logger([](const httplib::Request& req, const httplib::Response& res) {
    std::string line = req.remote_addr + " " + req.method + " " + req.target + " " + std::to_string(res.status) +
                       " " + std::to_string(res.body.size()) + " bytes";
    for (const char* header : {"X-Ganzfeld-Table", "Server-Timing"}) {
      if (!res.has_header(header)) continue;
      line += ' ';
      line += res.get_header_value(header);  // "baked", "reused", "joined"; "total;dur=MS"
    }
    log_line(line);
  });

  // httplib's default socket options set SO_REUSEPORT, with which a second `serve` on the same
  // port binds too and silently shares the connections; SO_REUSEADDR alone refuses it (and still
  // allows a restart while old connections linger in TIME_WAIT). The socket is kept to raise
  // its backlog after bind: listen() on a listening socket sets a new backlog (Linux, listen(2)).
  int listener = -1;
  server.set_socket_options([&listener](int sock) {
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listener = sock;
  });
  int port = options.port;
  const bool bound = port == 0 ? (port = server.bind_to_any_port(options.bind)) > 0 : server.bind_to_port(options.bind, port);
  if (!bound)
    throw InputError({"cannot listen on " + options.bind + ":" + std::to_string(options.port) +
                          " (address in use, not local, or not allowed); choose another ",
                      Named{"bind"}, " or ", Named{"port"}});
  if (listener >= 0) ::listen(listener, kListenBacklog);
  log_line("listening on http://" + options.bind + ":" + std::to_string(port) + "/ (cache " + service_options.cache_dir +
           ", " + std::to_string(service_options.jobs) + " bake jobs, " + std::to_string(service_options.queue) +
           " queued at most; " + std::to_string(options.threads) + " connection threads, " +
           std::to_string(options.waiting) + " connections waiting at most)");

  std::atomic<bool> signalled{false};
  std::thread waiter([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    signalled = true;
    log_line(std::string("shutting down on ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") +
             ": queued bakes are discarded, running ones finish");
    service.stop();  // waits for the running bakes; their requests are answered before the listener closes
    server.stop();
  });
  const bool served = server.listen_after_bind();
  if (!served && !signalled) pthread_kill(waiter.native_handle(), SIGTERM);  // the listener failed: wake the waiter
  waiter.join();
  log_line("stopped");
  return 0;
}

}  // namespace ganzfeld::serve
