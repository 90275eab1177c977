#include "serve/http.h"

#include <netdb.h>
#include <pthread.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include <httplib.h>

#include "models/registry.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::serve {

namespace {

std::mutex log_mutex;

/// Connections the kernel holds for the listener before the loop accepts them: a burst (16
/// load-test clients, a browser's parallel requests) must not lose SYNs, each lost one costing its
/// client a 1 s retransmission (RFC 6298 2.1). The kernel caps it at net.core.somaxconn.
constexpr int kListenBacklog = 128;
/// Requests left to the cheap endpoints when the others compute: ServiceOptions::max_computing
/// is the threads less these.
constexpr int kThreadsForCheapRequests = 4;

/// One line on stderr: "ganzfeld serve: MESSAGE".
void log_line(const std::string& message) {
  std::lock_guard lock(log_mutex);
  std::fprintf(stderr, "ganzfeld serve: %s\n", message.c_str());
  std::fflush(stderr);
}

/// The request of one worker (its Cancellation), for the handler that httplib calls on that thread.
thread_local const Cancellation* current_cancel = nullptr;

/// A request head in memory, and the answer httplib writes: the connection loop owns the socket.
class HeadStream final : public httplib::Stream {
 public:
  explicit HeadStream(const Exchange& exchange) : exchange_(exchange) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {  // the head, then end of stream (no body: request_head.h)
    const std::size_t n = std::min(size, exchange_.head.size() - position_);
    std::memcpy(ptr, exchange_.head.data() + position_, n);
    position_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    answer.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = exchange_.peer_ip;
    port = exchange_.peer_port;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = exchange_.local_ip;
    port = exchange_.local_port;
  }
  socket_t socket() const override { return INVALID_SOCKET; }

  std::string answer;

 private:
  const Exchange& exchange_;
  std::size_t position_ = 0;
};

/// cpp-httplib's request parser, router and answer writer, on a head in memory.
class Router final : public httplib::Server {
 public:
  Answer answer(const Exchange& exchange) {
    HeadStream stream(exchange);
    bool closed = false;
    process_request(stream, exchange.last, closed, nullptr);
    return {std::move(stream.answer), closed || exchange.last};
  }
};

/// A listening TCP socket on `bind`:`port` (0: any free port); its port. SO_REUSEADDR only:
/// httplib's default SO_REUSEPORT would let a second `serve` bind the same port and silently share
/// the connections; SO_REUSEADDR alone refuses it and still allows a restart while old
/// connections linger in TIME_WAIT.
std::pair<int, int> listen_on(const std::string& bind, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  const InputError refusal(
      {"cannot listen on " + bind + ":" + service + " (address in use, not local, or not allowed); choose another ",
       Named{"bind"}, " or ", Named{"port"}});
  if (getaddrinfo(bind.c_str(), service.c_str(), &hints, &found) != 0) throw refusal;
  int listener = -1;
  for (addrinfo* a = found; a && listener < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    const int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, kListenBacklog) == 0) listener = fd;
    else ::close(fd);
  }
  freeaddrinfo(found);
  if (listener < 0) throw refusal;
  sockaddr_storage bound{};
  socklen_t length = sizeof bound;
  getsockname(listener, reinterpret_cast<sockaddr*>(&bound), &length);
  const int actual = bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6&>(bound).sin6_port)
                                                 : ntohs(reinterpret_cast<sockaddr_in&>(bound).sin_port);
  return {listener, actual};
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// The host names a request may carry in its Host header (ServerOptions::allowed_hosts).
std::vector<std::string> allowed_host_names(const ServerOptions& options) {
  std::vector<std::string> names{"localhost", "127.0.0.1", "::1"};
  if (options.bind != "0.0.0.0" && options.bind != "::") names.push_back(options.bind);
  names.insert(names.end(), options.allowed_hosts.begin(), options.allowed_hosts.end());
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names)
    out += (out.empty() ? "" : ", ") + (n.find(':') != std::string::npos ? "[" + n + "]" : n);
  return out;
}

void wait_until(const std::function<bool()>& done, std::chrono::steady_clock::time_point deadline) {
  while (!done() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

}  // namespace

bool host_allowed(const std::string& host_header, const std::vector<std::string>& allowed) {
  std::string host = lower(host_header);
  if (host.empty()) return false;
  if (host.front() == '[') {  // an IPv6 literal, maybe with a port
    const std::size_t close = host.find(']');
    if (close == std::string::npos) return false;
    host = host.substr(1, close - 1);
  } else if (const std::size_t colon = host.find(':'); colon != std::string::npos) {
    if (host.find(':', colon + 1) != std::string::npos) return false;  // a bare IPv6 address is not a Host
    host = host.substr(0, colon);
  }
  return std::any_of(allowed.begin(), allowed.end(),
                     [&](const std::string& a) { return a == "*" || lower(a) == host; });
}

int run(const ServiceOptions& service_options, const ServerOptions& options) {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // inherited by every thread started below
  std::signal(SIGPIPE, SIG_IGN);                  // a vanished client is a send error, not a signal

  ConnectionLoop* loop_ptr = nullptr;  // for /healthz; set before the first request can arrive
  ServiceOptions so = service_options;
  so.log = log_line;
  so.max_computing = std::max(1, options.threads - kThreadsForCheapRequests);
  so.connection_stats = [&loop_ptr]() -> nlohmann::ordered_json {
    if (!loop_ptr) return nlohmann::ordered_json::object();
    const ConnectionLoop::Stats s = loop_ptr->stats();
    return {{"connections_open", s.open},       {"connections_working", s.working},
            {"connections_writing", s.writing}, {"connections_accepted", s.accepted},
            {"requests_shed", s.shed},          {"connections_timed_out", s.timed_out},
            {"heads_refused", s.refused_heads}, {"clients_gone", s.client_gone}};
  };
  Service service(so);
  const std::vector<std::string> hosts = allowed_host_names(options);

  Router router;
  router.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
  router.set_keep_alive_timeout(static_cast<time_t>(options.loop.idle_seconds));
  router.set_keep_alive_max_count(static_cast<std::size_t>(options.loop.max_requests_per_connection));
  router.set_pre_routing_handler([&hosts](const httplib::Request& req, httplib::Response& res) {
    const bool has_host = req.has_header("Host");
    if ((has_host || req.version != "HTTP/1.0") && !host_allowed(req.get_header_value("Host"), hosts)) {
      res.status = has_host ? 403 : 400;
      res.set_content(error_body(has_host ? "Host '" + req.get_header_value("Host").substr(0, 100) +
                                                "' is not served here; allowed: " + joined(hosts)
                                          : "an HTTP/1.1 request needs a Host header (RFC 9112, 3.2)"),
                      "application/json");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  router.Get(".*", [&service](const httplib::Request& req, httplib::Response& res) {
    const util::Stopwatch watch;
    const std::size_t mark = req.target.find('?');
    const std::string query = mark == std::string::npos ? "" : req.target.substr(mark + 1);
    const Reply reply = service.handle(req.path, query, req.get_header_value("If-None-Match"), current_cancel);
    res.status = reply.status;
    for (const auto& [name, value] : reply.headers) res.set_header(name, value);
    res.set_header("Server-Timing", "total;dur=" + std::to_string(watch.seconds() * 1000.0));
    if (reply.status != 304) res.set_content(reply.body, reply.content_type);
  });
  router.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string message = res.status == 414                        ? "request URI too long"
                                : res.status == 404 || res.status == 405 ? "only GET (and HEAD) requests are served"
                                                                         : "bad request";
    res.set_content(error_body(message), "application/json");
  });
  // Last word on every answer's headers, after httplib's own: a 304 has no body and so no
  // Content-Length or Content-Type of one (RFC 9110, 8.6 and 15.4.5; httplib writes "0"); Range
  // is not served (request_head.h), so no "Accept-Ranges: bytes" (httplib's on HEAD); only a 200 or
  // 304 names a cacheable body: an error carries no ETag and is never stored.
  router.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.status == 304) {
      res.headers.erase("Content-Length");
      res.headers.erase("Content-Type");
    }
    res.headers.erase("Accept-Ranges");
    res.set_header("Accept-Ranges", "none");
    if (res.status != 200 && res.status != 304) {
      res.headers.erase("ETag");
      res.headers.erase("Cache-Control");
      res.set_header("Cache-Control", "no-store");
    }
  });
  router.set_logger([](const httplib::Request& req, const httplib::Response& res) {
    std::string line = req.remote_addr + " " + req.method + " " + req.target + " " + std::to_string(res.status) + " " +
                       std::to_string(res.body.size()) + " bytes";
    for (const char* header : {"X-Ganzfeld-Table", "Server-Timing"}) {
      if (!res.has_header(header)) continue;
      line += ' ';
      line += res.get_header_value(header);  // "baked", "reused", "joined"; "total;dur=MS"
    }
    log_line(line);
  });

  const auto [listener, port] = listen_on(options.bind, options.port);
  WorkerPool workers(static_cast<std::size_t>(std::max(1, options.threads)),
                     static_cast<std::size_t>(std::max(0, options.waiting)));
  ConnectionLoop loop(
      listener, options.loop, workers,
      [&router](const Exchange& exchange) {
        current_cancel = exchange.cancel.get();
        Answer answer = router.answer(exchange);
        current_cancel = nullptr;
        return answer;
      },
      log_line);
  loop_ptr = &loop;
  log_line("listening on http://" + options.bind + ":" + std::to_string(port) + "/ (cache " + so.cache_dir + ", " +
           std::to_string(so.jobs) + " bake jobs, " + std::to_string(so.queue) + " queued at most; " +
           std::to_string(options.threads) + " connection threads, " + std::to_string(options.waiting) +
           " requests waiting at most; " + std::to_string(options.loop.max_connections) + " connections at most)");
  std::thread io([&loop] { loop.run(); });

  int signal = 0;
  sigwait(&signals, &signal);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto drain = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.drain_seconds));
  log_line(std::string("shutting down on ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + ": draining for " +
           format_number(options.drain_seconds) + " s, then what still runs is cancelled");
  service.drain();
  loop.drain();
  const auto quiet = [&] {
    const ConnectionLoop::Stats s = loop.stats();
    return s.working == 0 && s.writing == 0 && service.health()["bakes_running"] == 0;
  };
  wait_until(quiet, start + drain);
  loop.cancel_all(StopReason::shutdown);
  service.cancel_running();
  constexpr auto kCancelGrace = std::chrono::milliseconds(600);  // cancelled work answers 503 and is written
  wait_until(quiet, Clock::now() + kCancelGrace);
  loop.stop();
  io.join();
  ::close(listener);
  const long long still =
      static_cast<long long>(workers.stats().running) + service.health()["bakes_running"].get<long long>();
  if (still > 0) {  // work that did not stop when cancelled: the cache is safe (atomic files); exit anyway
    log_line("stopped with " + std::to_string(still) + " requests or bakes still running");
    std::_Exit(0);
  }
  workers.shutdown();
  service.stop();
  log_line("stopped");
  return 0;
}

}  // namespace ganzfeld::serve
