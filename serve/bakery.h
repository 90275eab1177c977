// Bakes on demand without an unbounded backlog (docs/serve.md): `jobs` worker threads take
// bakes (tables, and the spheres of /api/sphere that need a cubature per pixel) from a queue of
// at most `queue` waiting ones. Identical requests share one bake (single
// flight): while the bake of a key is queued or running, every further request for that key
// joins it instead of queueing another. A request that would need a new slot when all
// jobs + queue slots are taken is refused (Busy: HTTP 503 with Retry-After), as is every
// request once stop() has begun. Each bake is one tables::bake_or_reuse, which writes its file
// atomically, so the cache never holds a partial table whatever stop() interrupts.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tables/cache.h"

namespace ganzfeld::serve {

/// No capacity for another bake now, or the service is stopping: HTTP 503.
class Busy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Bakery {
 public:
  /// What a job makes: a table (tables::CacheResult) or a reply body (std::string); the caller
  /// that submitted the job knows which.
  using Result = std::shared_ptr<const void>;
  using Job = std::function<Result()>;

  /// `jobs` >= 1 bakes at once, `queue` >= 0 waiting.
  Bakery(int jobs, int queue);
  ~Bakery();  ///< stop()
  Bakery(const Bakery&) = delete;
  Bakery& operator=(const Bakery&) = delete;

  struct Ticket {
    std::shared_future<Result> result;  ///< the job's result or exception (Busy if discarded by stop())
    bool joined = false;                ///< true: the key was already queued or running
  };
  /// The bake of `key`: joins the one in flight, or queues `job`; throws Busy when every slot
  /// is taken or stop() has begun.
  Ticket submit(const std::string& key, Job job);

  /// Refuses new work, discards the queued jobs (their tickets throw Busy), lets running jobs
  /// finish and joins the workers. Idempotent.
  void stop();

  struct Stats {
    long long started = 0;    ///< jobs a worker ran
    long long joined = 0;     ///< requests that joined a bake in flight
    long long refused = 0;    ///< requests refused for want of a slot
    long long discarded = 0;  ///< queued jobs dropped by stop()
    int running = 0, queued = 0;
  };
  Stats stats() const;

 private:
  struct Pending {
    std::string key;
    Job job;
    std::promise<Result> promise;
  };
  void work();

  const int jobs_, queue_limit_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Pending> queue_;
  std::map<std::string, std::shared_future<Result>> flights_;  ///< queued or running, by key
  bool stopping_ = false;
  Stats stats_;
  std::vector<std::thread> workers_;
};

}  // namespace ganzfeld::serve
