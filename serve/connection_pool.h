// A bounded connection queue for cpp-httplib (never an unbounded backlog). Debian's
// cpp-httplib 0.11 hands every accepted connection to Server::new_task_queue, whose ThreadPool
// queues without limit: under a flood, connections wait for minutes, each holding a socket.
// This pool runs `threads` connections at once and lets at most `max_waiting` wait; a connection
// beyond them is served at once on the accepting thread in "shedding" mode, in which the
// handler answers 503 with Retry-After and Connection: close (http.cpp) without doing any work.
// (0.11's TaskQueue hands over an opaque closure, not the socket, so the only way to answer the
// connection is to run the closure; a shed answer costs microseconds. Connections arriving while
// the accepting thread sheds wait in the kernel's listen backlog, which is bounded too. A shed
// client that sends no request holds the accepting thread for httplib's read timeout, 5 s: a
// limit of this design, not of the bound.)
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include <httplib.h>

namespace ganzfeld::serve {

class ConnectionPool : public httplib::TaskQueue {
 public:
  ConnectionPool(std::size_t threads, std::size_t max_waiting);
  ~ConnectionPool() override;
  ConnectionPool(const ConnectionPool&) = delete;
  ConnectionPool& operator=(const ConnectionPool&) = delete;

  /// Queues `fn`, or runs it now in shedding mode when every thread is busy and max_waiting
  /// connections already wait.
  void enqueue(std::function<void()> fn) override;
  /// Runs what is queued, then joins the threads (httplib calls it when the listener stops).
  void shutdown() override;

  /// True on a thread running a shed connection: answer 503 and close.
  static bool shedding() noexcept;

  /// Connections shed so far by every pool of the process (tests/connection_pool_test.cpp).
  static long long shed_count() noexcept;

 private:
  void work();

  const std::size_t threads_count_, max_waiting_;
  std::size_t running_ = 0;  ///< connections a thread is serving
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> waiting_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace ganzfeld::serve
