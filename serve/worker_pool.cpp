#include "serve/worker_pool.h"

#include <algorithm>

namespace ganzfeld::serve {

WorkerPool::WorkerPool(std::size_t threads, std::size_t max_waiting)
    : threads_count_(std::max<std::size_t>(1, threads)), max_waiting_(max_waiting) {
  for (std::size_t k = 0; k < threads_count_; ++k) threads_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() { shutdown(); }

bool WorkerPool::try_submit(std::function<void()> task) {
  std::lock_guard lock(mutex_);
  if (stopping_ || running_ + waiting_.size() >= threads_count_ + max_waiting_) {
    ++refused_;
    return false;
  }
  waiting_.push_back(std::move(task));
  ready_.notify_one();
  return true;
}

void WorkerPool::work() {
  while (true) {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
    if (waiting_.empty()) return;  // stopping, nothing left
    std::function<void()> task = std::move(waiting_.front());
    waiting_.pop_front();
    ++running_;
    lock.unlock();
    task();
    lock.lock();
    --running_;
  }
}

void WorkerPool::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
}

WorkerPool::Stats WorkerPool::stats() const {
  std::lock_guard lock(mutex_);
  return {threads_count_, running_, waiting_.size(), refused_};
}

}  // namespace ganzfeld::serve
