#include "serve/bakery.h"

#include <algorithm>

namespace ganzfeld::serve {

Bakery::Bakery(int jobs, int queue) : jobs_(std::max(1, jobs)), queue_limit_(std::max(0, queue)) {
  for (int k = 0; k < jobs_; ++k) workers_.emplace_back([this] { work(); });
}

Bakery::~Bakery() { stop(); }

Bakery::Ticket Bakery::submit(const std::string& key, Job job) {
  std::lock_guard lock(mutex_);
  if (stopping_) throw Busy("the service is shutting down; no new bakes");
  if (const auto it = flights_.find(key); it != flights_.end()) {
    ++stats_.joined;
    return {it->second, true};
  }
  if (stats_.running + static_cast<int>(queue_.size()) >= jobs_ + queue_limit_) {
    ++stats_.refused;
    throw Busy("all " + std::to_string(jobs_) + " bake jobs and " + std::to_string(queue_limit_) +
               " queue slots are taken; retry later");
  }
  Pending pending{key, std::move(job), {}};
  std::shared_future<Result> result = pending.promise.get_future().share();
  flights_.emplace(key, result);
  queue_.push_back(std::move(pending));
  ++stats_.queued;
  ready_.notify_one();
  return {result, false};
}

void Bakery::work() {
  while (true) {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, and stop() discarded what was queued
    Pending pending = std::move(queue_.front());
    queue_.pop_front();
    --stats_.queued;
    ++stats_.running;
    ++stats_.started;
    lock.unlock();
    try {
      pending.promise.set_value(pending.job());
    } catch (...) {
      pending.promise.set_exception(std::current_exception());
    }
    lock.lock();
    --stats_.running;
    flights_.erase(pending.key);  // later requests find the file in the cache
  }
}

void Bakery::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (Pending& pending : queue_) {
      pending.promise.set_exception(std::make_exception_ptr(Busy("the service shut down before this bake started")));
      flights_.erase(pending.key);
      ++stats_.discarded;
    }
    stats_.queued = 0;
    queue_.clear();
  }
  ready_.notify_all();
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
