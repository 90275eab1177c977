#include "serve/connection_pool.h"

#include <algorithm>
#include <atomic>

namespace ganzfeld::serve {

namespace {
thread_local bool tls_shedding = false;
std::atomic<long long> shed_total{0};
}  // namespace

ConnectionPool::ConnectionPool(std::size_t threads, std::size_t max_waiting)
    : threads_count_(std::max<std::size_t>(1, threads)), max_waiting_(max_waiting) {
  for (std::size_t k = 0; k < threads_count_; ++k) threads_.emplace_back([this] { work(); });
}

ConnectionPool::~ConnectionPool() { shutdown(); }

void ConnectionPool::enqueue(std::function<void()> fn) {
  {
    std::lock_guard lock(mutex_);
    if (running_ + waiting_.size() < threads_count_ + max_waiting_ && !stopping_) {
      waiting_.push_back(std::move(fn));
      ready_.notify_one();
      return;
    }
  }
  ++shed_total;
  tls_shedding = true;
  fn();  // answers 503 and closes the socket (the closure is httplib's process_and_close_socket)
  tls_shedding = false;
}

void ConnectionPool::work() {
  while (true) {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
    if (waiting_.empty()) return;  // stopping, nothing left
    std::function<void()> fn = std::move(waiting_.front());
    waiting_.pop_front();
    ++running_;
    lock.unlock();
    fn();
    lock.lock();
    --running_;
  }
}

void ConnectionPool::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
}

bool ConnectionPool::shedding() noexcept { return tls_shedding; }

long long ConnectionPool::shed_count() noexcept { return shed_total.load(); }

}  // namespace ganzfeld::serve
