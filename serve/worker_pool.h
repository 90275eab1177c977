// The threads that answer requests (serve/connection_loop.h hands them complete request heads):
// `threads` run at once and at most `max_waiting` wait; try_submit refuses one more, and the loop
// answers it 503 with Retry-After at once, so there is never an unbounded backlog. A worker never
// touches a socket: it turns a request head into answer bytes, so slow or idle clients hold no
// worker.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ganzfeld::serve {

class WorkerPool {
 public:
  WorkerPool(std::size_t threads, std::size_t max_waiting);
  ~WorkerPool();  ///< shutdown()
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `task`, or returns false when every thread is busy and max_waiting tasks already
  /// wait (or shutdown() has begun).
  bool try_submit(std::function<void()> task);
  /// Runs what is queued, then joins the threads. Idempotent.
  void shutdown();

  struct Stats {
    std::size_t threads = 0, running = 0, waiting = 0;
    long long refused = 0;  ///< try_submit calls that returned false
  };
  Stats stats() const;

 private:
  void work();

  const std::size_t threads_count_, max_waiting_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> waiting_;
  std::size_t running_ = 0;
  long long refused_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace ganzfeld::serve
