#include "serve/connection_loop.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>
#include <cerrno>

#include <stdexcept>

#include "serve/service.h"

namespace ganzfeld::serve {

namespace {

constexpr std::uint64_t kListenerId = 0, kWakeId = 1;
/// How often deadlines are looked at; also the longest epoll_wait.
constexpr auto kTick = std::chrono::milliseconds(20);
/// After EMFILE (no descriptor left to accept with), the listener rests this long.
constexpr auto kAcceptPause = std::chrono::milliseconds(100);
/// How long a closing connection reads and drops what its client still sends (State::lingering).
constexpr double kLingerSeconds = 2.0;
/// Connections beyond LoopOptions::max_connections held at once to be answered 503 and closed;
/// beyond these, a connection is closed without an answer.
constexpr std::size_t kRefusing = 64;

const char* reason_phrase(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 408: return "Request Timeout";
    case 413: return "Content Too Large";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
  }
  return "Error";
}

std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}

std::pair<std::string, int> address(const sockaddr_storage& a) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    return {text, ntohs(v4.sin_port)};
  }
  if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    return {text, ntohs(v6.sin6_port)};
  }
  return {"?", 0};
}

/// "METHOD TARGET" of a request line (for the log), without the version.
std::string method_and_target(const std::string& request_line) {
  const std::size_t version = request_line.rfind(" HTTP/");
  return version == std::string::npos ? request_line : request_line.substr(0, version);
}

}  // namespace

std::string local_answer(int status, const std::string& message, bool retry) {
  const std::string body = error_body(message);
  std::string text = "HTTP/1.1 " + std::to_string(status) + " " + reason_phrase(status) +
                     "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                     "\r\nConnection: close\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n";
  if (retry) text += "Retry-After: " + std::to_string(kRetryAfterSeconds) + "\r\n";
  return text + "\r\n" + body;
}

ConnectionLoop::ConnectionLoop(int listener, LoopOptions options, WorkerPool& workers, Respond respond, Log log)
    : listener_(listener), options_(options), workers_(workers), respond_(std::move(respond)), log_(std::move(log)) {
  epoll_ = epoll_create1(EPOLL_CLOEXEC);
  wake_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (epoll_ < 0 || wake_ < 0) throw std::runtime_error("cannot create the connection loop's epoll or eventfd");
  fcntl(listener_, F_SETFL, fcntl(listener_, F_GETFL) | O_NONBLOCK);
  epoll_event listen{EPOLLIN, {.u64 = kListenerId}}, wakeup{EPOLLIN, {.u64 = kWakeId}};
  epoll_ctl(epoll_, EPOLL_CTL_ADD, listener_, &listen);
  epoll_ctl(epoll_, EPOLL_CTL_ADD, wake_, &wakeup);
}

ConnectionLoop::~ConnectionLoop() {
  for (auto& [id, c] : connections_)
    if (c.fd >= 0) ::close(c.fd);
  ::close(wake_);
  ::close(epoll_);
}

void ConnectionLoop::wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_, &one, sizeof one);
}

void ConnectionLoop::drain() {
  draining_ = true;
  wake();
}

void ConnectionLoop::cancel_all(StopReason why) {
  cancel_all_ = why;
  wake();
}

void ConnectionLoop::stop() {
  stopping_ = true;
  wake();
}

ConnectionLoop::Stats ConnectionLoop::stats() const {
  return {open_.load(), working_.load(),   writing_.load(),       accepted_.load(),
          shed_.load(), timed_out_.load(), refused_heads_.load(), client_gone_.load()};
}

void ConnectionLoop::run() {
  std::vector<epoll_event> events(128);
  last_sweep_ = Clock::now();
  while (!stopping_) {
    const int n = epoll_wait(epoll_, events.data(), static_cast<int>(events.size()), static_cast<int>(kTick.count()));
    for (int k = 0; k < n; ++k) {
      const std::uint64_t id = events[k].data.u64;
      if (id == kListenerId) {
        accept_all();
      } else if (id == kWakeId) {
        std::uint64_t count = 0;
        [[maybe_unused]] const ssize_t r = ::read(wake_, &count, sizeof count);
      } else if (const auto it = connections_.find(id); it != connections_.end() && it->second.fd >= 0) {
        on_event(it->second, events[k].events);
      }
    }
    std::vector<std::pair<std::uint64_t, Answer>> answers;
    {
      std::lock_guard lock(answers_mutex_);
      answers.swap(answers_);
    }
    for (auto& [id, answer] : answers) on_answer(id, std::move(answer));
    if (Clock::now() - last_sweep_ >= kTick || draining_ || cancel_all_ != StopReason::none) sweep();
    for (const std::uint64_t id : closed_) connections_.erase(id);
    closed_.clear();
  }
  for (auto& [id, c] : connections_) close(c);
  connections_.clear();
  epoll_ctl(epoll_, EPOLL_CTL_DEL, listener_, nullptr);
}

void ConnectionLoop::accept_all() {
  while (true) {
    sockaddr_storage peer{};
    socklen_t length = sizeof peer;
    const int fd = accept4(listener_, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      if (errno == EMFILE || errno == ENFILE) {  // no descriptor to accept with: rest instead of spinning
        epoll_ctl(epoll_, EPOLL_CTL_DEL, listener_, nullptr);
        listener_paused_until_ = Clock::now() + kAcceptPause;
        log_("out of file descriptors; not accepting for " + std::to_string(kAcceptPause.count()) + " ms");
      }
      return;  // EAGAIN: accepted everything that waited
    }
    ++accepted_;
    const bool over = connections_.size() >= options_.max_connections;
    if (over && connections_.size() >= options_.max_connections + kRefusing) {
      ::close(fd);  // refusing as many as it can already: the kernel's backlog is the only other queue
      ++shed_;
      continue;
    }
    const int yes = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);  // answers leave in one piece, at once
    sockaddr_storage local{};
    socklen_t local_length = sizeof local;
    getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_length);
    Connection c;
    c.fd = fd;
    c.id = next_id_++;
    std::tie(c.peer_ip, c.peer_port) = address(peer);
    std::tie(c.local_ip, c.local_port) = address(local);
    c.deadline = Clock::now() + seconds(options_.idle_seconds);
    epoll_event event{EPOLLIN | EPOLLRDHUP, {.u64 = c.id}};
    epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &event);
    Connection& added = connections_.emplace(c.id, std::move(c)).first->second;
    ++open_;
    if (over) {  // answered 503 at once, then closed like any answer with Connection: close
      ++shed_;
      answer_locally(added, 503,
                     "all " + std::to_string(options_.max_connections) + " connections are open; retry later", true,
                     "-");
    }
  }
}

void ConnectionLoop::on_event(Connection& c, std::uint32_t events) {
  switch (c.state) {
    case State::reading: read_some(c); break;
    case State::working:  // armed once (EPOLLONESHOT) for the peer closing: stop the work
      if (events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR)) {
        c.peer_closed = true;
        ++client_gone_;
        if (c.cancel) c.cancel->cancel(StopReason::client_gone);
      }
      break;
    case State::writing:
      if (events & EPOLLERR) close(c);
      else flush(c);
      break;
    case State::lingering: {
      char scratch[16384];
      ssize_t n;
      while ((n = ::recv(c.fd, scratch, sizeof scratch, 0)) > 0) {}
      if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) close(c);
      break;
    }
  }
}

void ConnectionLoop::read_some(Connection& c) {
  char buffer[16384];
  while (c.in.size() <= options_.max_head_bytes) {  // beyond: 431 below, whatever else arrives
    const ssize_t n = ::recv(c.fd, buffer, sizeof buffer, 0);
    if (n > 0) {
      c.in.append(buffer, static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0) {
      c.peer_closed = true;
      break;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) break;
    close(c);  // reset by the peer
    return;
  }
  take_heads(c);
}

void ConnectionLoop::take_heads(Connection& c) {
  if (c.fd < 0 || c.state != State::reading) return;
  if (c.in.empty()) {
    if (c.peer_closed) close(c);
    return;
  }
  if (!c.head_started) {
    c.head_started = true;
    c.deadline = Clock::now() + seconds(options_.header_seconds);
  }
  HeadScan scan = scan_head(c.in, options_.max_head_bytes);
  switch (scan.verdict) {
    case HeadScan::Verdict::incomplete:
      if (c.peer_closed) close(c);  // the client stopped sending in the middle of a head
      return;
    case HeadScan::Verdict::refused:
      ++refused_heads_;
      answer_locally(c, scan.status, scan.message, false, scan.request_line);
      return;
    case HeadScan::Verdict::complete:
      c.in.erase(0, scan.consumed);
      dispatch(c, std::move(scan));
      return;
  }
}

void ConnectionLoop::dispatch(Connection& c, HeadScan&& scan) {
  ++c.served;
  auto cancel = std::make_shared<Cancellation>();
  Exchange exchange{std::move(scan.head),
                    c.peer_ip,
                    c.local_ip,
                    c.peer_port,
                    c.local_port,
                    c.served >= options_.max_requests_per_connection || draining_ || c.peer_closed,
                    cancel};
  const std::uint64_t id = c.id;
  c.state = State::working;  // before the worker can run, so that /healthz counts its own request
  ++working_;
  const bool queued = workers_.try_submit([this, id, exchange = std::move(exchange)] {
    Answer answer = respond_(exchange);
    {
      std::lock_guard lock(answers_mutex_);
      answers_.emplace_back(id, std::move(answer));
    }
    wake();
  });
  if (!queued) {
    c.state = State::reading;
    --working_;
    ++shed_;
    const WorkerPool::Stats s = workers_.stats();
    answer_locally(c, 503,
                   "all " + std::to_string(s.threads) + " connection threads are busy and " +
                       std::to_string(s.waiting) + " requests wait; retry later",
                   true, scan.request_line);
    return;
  }
  c.cancel = std::move(cancel);
  c.deadline = Clock::now() + seconds(options_.request_seconds);
  arm(c, EPOLLRDHUP | EPOLLONESHOT);
}

void ConnectionLoop::answer_locally(Connection& c, int status, const std::string& message, bool retry,
                                    const std::string& line) {
  const std::string answer = local_answer(status, message, retry);
  log_(c.peer_ip + " " + method_and_target(line) + " " + std::to_string(status) + " " + std::to_string(answer.size()) +
       " bytes (" + message + ")");
  c.in.clear();
  c.out += answer;
  c.close_after = true;
  c.state = State::writing;
  ++writing_;
  c.deadline = Clock::now() + seconds(options_.write_seconds);
  flush(c);
}

void ConnectionLoop::on_answer(std::uint64_t id, Answer&& answer) {
  const auto it = connections_.find(id);
  if (it == connections_.end() || it->second.fd < 0) return;  // closed meanwhile (a deadline, shutdown)
  Connection& c = it->second;
  c.cancel.reset();
  --working_;
  ++writing_;
  c.state = State::writing;
  c.out += answer.bytes;
  c.close_after = c.close_after || answer.close;
  c.deadline = Clock::now() + seconds(options_.write_seconds);
  flush(c);
}

void ConnectionLoop::flush(Connection& c) {
  while (c.sent < c.out.size()) {
    const ssize_t n = ::send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
    if (n > 0) {
      c.sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      arm(c, EPOLLOUT);
      return;
    }
    close(c);  // the peer is gone
    return;
  }
  c.out.clear();
  c.sent = 0;
  --writing_;
  if (c.close_after) {
    c.state = State::lingering;
    c.deadline = Clock::now() + seconds(kLingerSeconds);
    ::shutdown(c.fd, SHUT_WR);
    arm(c, EPOLLIN | EPOLLRDHUP);
    return;
  }
  c.state = State::reading;
  c.head_started = false;
  c.deadline = Clock::now() + seconds(options_.idle_seconds);
  arm(c, EPOLLIN | EPOLLRDHUP);
  take_heads(c);  // a pipelined request already read
}

void ConnectionLoop::arm(Connection& c, std::uint32_t events) {
  epoll_event event{events, {.u64 = c.id}};
  epoll_ctl(epoll_, EPOLL_CTL_MOD, c.fd, &event);
}

void ConnectionLoop::close(Connection& c) {
  if (c.fd < 0) return;
  if (c.state == State::working) --working_;
  if (c.state == State::writing) --writing_;
  if (c.cancel) c.cancel->cancel(StopReason::client_gone);
  epoll_ctl(epoll_, EPOLL_CTL_DEL, c.fd, nullptr);
  ::close(c.fd);
  c.fd = -1;
  --open_;
  closed_.push_back(c.id);
}

void ConnectionLoop::sweep() {
  const Clock::time_point now = Clock::now();
  last_sweep_ = now;
  if (listener_paused_until_ != Clock::time_point{} && now >= listener_paused_until_) {
    epoll_event listen{EPOLLIN, {.u64 = kListenerId}};
    epoll_ctl(epoll_, EPOLL_CTL_ADD, listener_, &listen);
    listener_paused_until_ = {};
  }
  const StopReason cancel_all = cancel_all_.exchange(StopReason::none);
  for (auto& [id, c] : connections_) {
    if (c.fd < 0) continue;
    if (cancel_all != StopReason::none && c.cancel) c.cancel->cancel(cancel_all);
    if (c.state == State::reading && !c.head_started && c.served > 0 && draining_) {
      close(c);  // kept alive and idle while shutting down (a new one may be a health check: it is answered)
      continue;
    }
    if (now < c.deadline) continue;
    switch (c.state) {
      case State::reading:
        ++timed_out_;
        if (c.head_started)
          answer_locally(c, 408,
                         "the request head did not arrive whole within " +
                             std::to_string(static_cast<int>(options_.header_seconds)) + " s",
                         false, scan_head(c.in, options_.max_head_bytes).request_line);
        else close(c);  // idle beyond the keep-alive time
        break;
      case State::working:
        c.cancel->cancel(StopReason::deadline);
        c.deadline = Clock::time_point::max();  // once; the worker answers 503 (serve/cancellation.h)
        break;
      case State::writing:
        ++timed_out_;
        close(c);  // the client does not take its answer
        break;
      case State::lingering: close(c); break;
    }
  }
}

}  // namespace ganzfeld::serve
