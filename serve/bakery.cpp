#include "serve/bakery.h"

#include <algorithm>
#include <chrono>

#include "util/error.h"

namespace ganzfeld::serve {

namespace {
using Clock = std::chrono::steady_clock;
/// How often a waiter looks at its request's flag and the bake's budget.
constexpr auto kWaitPoll = std::chrono::milliseconds(20);
}  // namespace

struct Bakery::Flight {
  std::string key;
  std::promise<Result> promise;
  std::shared_future<Result> result = promise.get_future().share();
  std::atomic<bool> cancel{false};
  std::atomic<StopReason> why{StopReason::none};
  int waiters = 0;       ///< under the bakery's mutex
  bool running = false;  ///< under the bakery's mutex
  /// When its budget ends (steady-clock ticks): set when it starts running, read by waiters.
  std::atomic<Clock::rep> deadline{Clock::time_point::max().time_since_epoch().count()};

  void stop(StopReason reason) {
    StopReason none = StopReason::none;
    why.compare_exchange_strong(none, reason);
    cancel = true;
  }
};

Bakery::Bakery(int jobs, int queue, double budget_seconds)
    : jobs_(std::max(1, jobs)), queue_limit_(std::max(0, queue)), budget_seconds_(budget_seconds) {
  for (int k = 0; k < jobs_; ++k) workers_.emplace_back([this] { work(); });
}

Bakery::~Bakery() { stop(); }

Bakery::Ticket Bakery::submit(const std::string& key, Job job) {
  std::lock_guard lock(mutex_);
  if (draining_) throw Busy("the service is shutting down; no new bakes");
  if (const auto it = flights_.find(key); it != flights_.end()) {
    ++stats_.joined;
    ++it->second->waiters;
    return {it->second, true};
  }
  if (stats_.running + static_cast<int>(queue_.size()) >= jobs_ + queue_limit_) {
    ++stats_.refused;
    throw Busy("all " + std::to_string(jobs_) + " bake jobs and " + std::to_string(queue_limit_) +
               " queue slots are taken; retry later");
  }
  auto flight = std::make_shared<Flight>();
  flight->key = key;
  flight->waiters = 1;
  flights_.emplace(key, flight);
  queue_.push_back({flight, std::move(job)});
  ++stats_.queued;
  ready_.notify_one();
  return {flight, false};
}

Bakery::Result Bakery::wait(const Ticket& ticket, const Cancellation* request) {
  Flight& flight = *ticket.flight;
  while (flight.result.wait_for(kWaitPoll) != std::future_status::ready) {
    if (request && request->cancelled()) {
      leave(ticket.flight);
      throw Cancelled(stop_message(request->reason(), budget_seconds_));
    }
    if (Clock::now().time_since_epoch().count() > flight.deadline.load()) flight.stop(StopReason::deadline);
  }
  return flight.result.get();
}

void Bakery::leave(const std::shared_ptr<Flight>& flight) {
  std::lock_guard lock(mutex_);
  if (--flight->waiters > 0) return;
  if (flight->running) {
    flight->stop(StopReason::client_gone);  // nobody waits for it any more
    return;
  }
  const auto queued = std::find_if(queue_.begin(), queue_.end(), [&](const Pending& p) { return p.flight == flight; });
  if (queued == queue_.end()) return;  // already finished
  queue_.erase(queued);
  --stats_.queued;
  ++stats_.discarded;
  flights_.erase(flight->key);
  flight->promise.set_exception(std::make_exception_ptr(Cancelled("nobody waits for this bake any more")));
}

void Bakery::work() {
  while (true) {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return draining_ || !queue_.empty(); });
    if (queue_.empty()) return;  // draining, and drain() discarded what was queued
    Pending pending = std::move(queue_.front());
    queue_.pop_front();
    Flight& flight = *pending.flight;
    --stats_.queued;
    ++stats_.running;
    ++stats_.started;
    flight.running = true;
    const auto budget =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::min(budget_seconds_, 1e9)));
    flight.deadline = (Clock::now() + budget).time_since_epoch().count();
    lock.unlock();
    try {
      flight.promise.set_value(pending.job(flight.cancel));
    } catch (const Cancelled&) {
      flight.promise.set_exception(
          std::make_exception_ptr(Cancelled(stop_message(flight.why.load(), budget_seconds_))));
    } catch (...) { flight.promise.set_exception(std::current_exception()); }
    lock.lock();
    --stats_.running;
    if (flight.cancel) ++stats_.cancelled;
    flights_.erase(flight.key);  // later requests find the file in the cache
  }
}

void Bakery::drain() {
  std::lock_guard lock(mutex_);
  draining_ = true;
  for (Pending& pending : queue_) {
    pending.flight->promise.set_exception(
        std::make_exception_ptr(Busy("the service shut down before this bake started")));
    flights_.erase(pending.flight->key);
    ++stats_.discarded;
  }
  stats_.queued = 0;
  queue_.clear();
  ready_.notify_all();
}

void Bakery::cancel_running() {
  std::lock_guard lock(mutex_);
  for (const auto& [key, flight] : flights_)
    if (flight->running) flight->stop(StopReason::shutdown);
}

void Bakery::stop() {
  drain();
  for (std::thread& worker : workers_)
    if (worker.joinable()) worker.join();
  std::lock_guard lock(mutex_);
  workers_.clear();
}

Bakery::Stats Bakery::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace ganzfeld::serve
