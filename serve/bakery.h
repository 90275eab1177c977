// Bakes on demand without an unbounded backlog (docs/serve.md): `jobs` worker threads take
// bakes from a queue of at most `queue` waiting ones. Identical requests share one bake (single
// flight): while the bake of a key is queued or running, every further request for that key
// joins it instead of queueing another. A request that would need a new slot when all
// jobs + queue slots are taken is refused (Busy: HTTP 503 with Retry-After), as is every
// request once drain() has begun. Each bake is one tables::bake_or_reuse, which writes its file
// atomically, so the cache never holds a partial table whatever stops it.
//
// Every bake is bounded: it is cancelled (its flag, tables::BakeCommon::cancel) once nobody
// waits for it any more (the last waiter's request was cancelled: deadline, client gone), once it
// has run longer than its budget, or by cancel_running() at shutdown; its waiters then get
// Cancelled, and nothing is written.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "serve/cancellation.h"
#include "tables/cache.h"

namespace ganzfeld::serve {

/// No capacity for another bake now, or the service is stopping: HTTP 503.
class Busy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Bakery {
 public:
  using Result = std::shared_ptr<const tables::CacheResult>;
  /// One bake: reads `cancel` (tables::BakeCommon::cancel) and throws Cancelled once it is set.
  using Job = std::function<Result(const std::atomic<bool>& cancel)>;

  /// `jobs` >= 1 bakes at once, `queue` >= 0 waiting; a bake running longer than
  /// `budget_seconds` is cancelled.
  Bakery(int jobs, int queue, double budget_seconds = std::numeric_limits<double>::infinity());
  ~Bakery();  ///< stop()
  Bakery(const Bakery&) = delete;
  Bakery& operator=(const Bakery&) = delete;

  struct Flight;
  struct Ticket {
    std::shared_ptr<Flight> flight;
    bool joined = false;  ///< true: the key was already queued or running
  };
  /// The bake of `key`: joins the one in flight, or queues `job`; throws Busy when every slot
  /// is taken or drain() has begun. The caller is one of the bake's waiters until wait() returns.
  Ticket submit(const std::string& key, Job job);

  /// The bake's result, or its exception (Busy if drain() discarded it, Cancelled if it was
  /// cancelled). While it waits, a set `request` makes the caller leave the bake (the last
  /// waiter to leave cancels it) and throws Cancelled with the request's reason.
  Result wait(const Ticket& ticket, const Cancellation* request);

  /// Refuses new work and discards the queued jobs (their tickets throw Busy); running jobs go on.
  void drain();
  /// Sets the flag of every running bake (their waiters get Cancelled: shutting down).
  void cancel_running();
  /// drain(), then joins the workers once the running jobs have ended. Idempotent.
  void stop();

  struct Stats {
    long long started = 0;    ///< jobs a worker ran
    long long joined = 0;     ///< requests that joined a bake in flight
    long long refused = 0;    ///< requests refused for want of a slot
    long long discarded = 0;  ///< queued jobs dropped by drain() or left by every waiter
    long long cancelled = 0;  ///< running jobs cancelled (nobody waiting, over budget, shutdown)
    int running = 0, queued = 0;
  };
  Stats stats() const;

 private:
  struct Pending {
    std::shared_ptr<Flight> flight;
    Job job;
  };
  void work();
  void leave(const std::shared_ptr<Flight>& flight);

  const int jobs_, queue_limit_;
  const double budget_seconds_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Pending> queue_;
  std::map<std::string, std::shared_ptr<Flight>> flights_;  ///< queued or running, by key
  bool draining_ = false;
  Stats stats_;
  std::vector<std::thread> workers_;
};

}  // namespace ganzfeld::serve
