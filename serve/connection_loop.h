// Every socket of `ganzfeld serve` in one thread (Linux epoll): connections are accepted, request
// heads read, answers written and deadlines kept here, without a thread per connection, so a
// client that is slow to send its head (slowloris), keeps a connection idle, or never reads its
// answer holds no worker (serve/worker_pool.h). A complete head goes to a worker, which turns it
// into answer bytes (http.cpp: cpp-httplib parses and routes it); the loop writes them. What
// nginx calls client_header_timeout and send_timeout, and Go's http.Server ReadHeaderTimeout and
// WriteTimeout, are kept here (docs/serve.md, "Limits"):
//   idle      a kept-alive connection waits this long for the first byte of its next request;
//   header    a request head must be whole within this from its first byte (else 408, closed);
//   request   a request's work (a worker's) is cancelled this long after its head arrived
//             (serve/cancellation.h), and also when its client closes the connection;
//   write     an answer must be taken by the client within this (else the connection is closed).
// Connections beyond max_connections, and heads that find no worker and no queue slot, are
// answered 503 with Retry-After and closed at once. One request of a connection is answered at a
// time, in order: pipelined requests wait in the buffer until the answer before them is written.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "serve/cancellation.h"
#include "serve/request_head.h"
#include "serve/worker_pool.h"

namespace ganzfeld::serve {

struct LoopOptions {
  std::size_t max_connections = 512;  ///< open at once; beyond: 503 and closed
  double idle_seconds = 5.0;
  double header_seconds = 10.0;
  double request_seconds = 60.0;
  double write_seconds = 30.0;
  std::size_t max_head_bytes = 32 * 1024;  ///< beyond: 431
  int max_requests_per_connection = 1000;  ///< the last one is answered with Connection: close
};

/// One request for a worker.
struct Exchange {
  std::string head;  ///< complete, through its empty line (scan_head: no Range, no body)
  std::string peer_ip, local_ip;
  int peer_port = 0, local_port = 0;
  bool last = false;  ///< answer with Connection: close
  std::shared_ptr<const Cancellation> cancel;
};

/// What the worker hands back: the whole answer, and whether to close after it.
struct Answer {
  std::string bytes;
  bool close = false;
};

/// An answer the loop gives itself (503, 408, 413, 431, 400): status line, a JSON error body,
/// Connection: close, no-store, nosniff, and Retry-After when `retry`.
std::string local_answer(int status, const std::string& message, bool retry);

class ConnectionLoop {
 public:
  using Respond = std::function<Answer(const Exchange&)>;  ///< runs on a worker
  using Log = std::function<void(const std::string&)>;

  /// `listener`: a bound, listening socket (made non-blocking here). The loop must outlive the
  /// pool's work: shut the pool down after run() returns and before the loop is destroyed.
  ConnectionLoop(int listener, LoopOptions options, WorkerPool& workers, Respond respond, Log log);
  ~ConnectionLoop();
  ConnectionLoop(const ConnectionLoop&) = delete;
  ConnectionLoop& operator=(const ConnectionLoop&) = delete;

  /// Serves until stop(); then closes every connection and the listener.
  void run();

  // Thread-safe controls for shutdown (http.cpp), applied by the loop within a tick.
  void drain();                     ///< every later answer closes its connection; idle connections are closed
  void cancel_all(StopReason why);  ///< cancels every request a worker holds
  void stop();

  struct Stats {
    long long open = 0, working = 0, writing = 0;  ///< connections now
    long long accepted = 0, shed = 0, timed_out = 0, refused_heads = 0, client_gone = 0;
  };
  Stats stats() const;

 private:
  /// lingering: the answer before a close is written and the sending side shut; what the client
  /// still sends is read and dropped until it closes too (or a short while passes), so that the
  /// close does not reset the connection before the client has read the answer (RFC 9112, 9.6).
  enum class State { reading, working, writing, lingering };
  using Clock = std::chrono::steady_clock;
  struct Connection {
    int fd = -1;
    std::uint64_t id = 0;
    std::string peer_ip, local_ip;
    int peer_port = 0, local_port = 0;
    State state = State::reading;
    std::string in, out;
    std::size_t sent = 0;
    bool head_started = false, peer_closed = false, close_after = false;
    int served = 0;
    Clock::time_point deadline;
    std::shared_ptr<Cancellation> cancel;  ///< while a worker holds the request
  };

  void accept_all();
  void on_event(Connection& c, std::uint32_t events);
  void read_some(Connection& c);
  void take_heads(Connection& c);
  void dispatch(Connection& c, HeadScan&& scan);
  void answer_locally(Connection& c, int status, const std::string& message, bool retry, const std::string& line);
  void on_answer(std::uint64_t id, Answer&& answer);
  void flush(Connection& c);
  void close(Connection& c);
  void arm(Connection& c, std::uint32_t events);
  void sweep();
  void wake();

  const int listener_;
  const LoopOptions options_;
  WorkerPool& workers_;
  const Respond respond_;
  const Log log_;
  int epoll_ = -1, wake_ = -1;
  std::unordered_map<std::uint64_t, Connection> connections_;
  std::vector<std::uint64_t> closed_;
  std::uint64_t next_id_ = 2;                  ///< 0: the listener, 1: the wake-up event
  Clock::time_point listener_paused_until_{};  ///< after EMFILE; epoch: not paused
  Clock::time_point last_sweep_;

  std::mutex answers_mutex_;
  std::vector<std::pair<std::uint64_t, Answer>> answers_;
  std::atomic<bool> stopping_{false}, draining_{false};
  std::atomic<StopReason> cancel_all_{StopReason::none};
  std::atomic<long long> open_{0}, working_{0}, writing_{0}, accepted_{0}, shed_{0}, timed_out_{0}, refused_heads_{0},
      client_gone_{0};
};

}  // namespace ganzfeld::serve
