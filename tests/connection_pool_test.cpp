// serve/connection_pool.h: at most `threads` connections run at once and `max_waiting` wait;
// one more is run at once on the caller's thread in shedding mode (answered 503 by http.cpp).
// tests/serve_load_test.sh checks the same through real sockets.
#include <atomic>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "serve/connection_pool.h"

namespace ganzfeld::serve {
namespace {

/// A task that holds its thread until `release` is set, recording whether it ran shedding.
struct Held {
  std::promise<void> started;
  std::shared_future<void> release;
  std::atomic<bool> shed{true};
  std::function<void()> task() {
    return [this] {
      shed = ConnectionPool::shedding();
      started.set_value();
      release.wait();
    };
  }
};

TEST(ConnectionPool, ShedsOnlyBeyondThreadsAndQueue) {
  constexpr std::size_t kThreads = 2, kWaiting = 1;
  std::promise<void> release;
  const std::shared_future<void> released = release.get_future().share();
  ConnectionPool pool(kThreads, kWaiting);
  Held running[kThreads];
  for (Held& h : running) {
    h.release = released;
    pool.enqueue(h.task());
    h.started.get_future().wait();  // a thread holds it
  }
  std::atomic<int> waited_ran{0};
  std::atomic<bool> waited_shed{true};
  pool.enqueue([&] {  // waits: every thread is busy, the queue has room
    waited_shed = ConnectionPool::shedding();
    ++waited_ran;
  });
  const long long shed_before = ConnectionPool::shed_count();
  bool shed_here = false;
  std::thread::id ran_on;
  pool.enqueue([&] {  // beyond threads + queue: runs now, on this thread, shedding
    shed_here = ConnectionPool::shedding();
    ran_on = std::this_thread::get_id();
  });
  EXPECT_TRUE(shed_here);
  EXPECT_EQ(ran_on, std::this_thread::get_id());
  EXPECT_EQ(ConnectionPool::shed_count(), shed_before + 1);
  EXPECT_FALSE(ConnectionPool::shedding());  // the caller's thread is itself again
  EXPECT_EQ(waited_ran.load(), 0);           // still waiting for a thread
  release.set_value();
  pool.shutdown();  // runs what waits, then joins
  EXPECT_EQ(waited_ran.load(), 1);
  EXPECT_FALSE(waited_shed.load());
  for (const Held& h : running) EXPECT_FALSE(h.shed.load());
}

TEST(ConnectionPool, ZeroQueueShedsWhenEveryThreadIsBusy) {
  std::promise<void> release;
  ConnectionPool pool(1, 0);
  Held running;
  running.release = release.get_future().share();
  pool.enqueue(running.task());
  running.started.get_future().wait();
  bool shed = false;
  pool.enqueue([&] { shed = ConnectionPool::shedding(); });
  EXPECT_TRUE(shed);
  release.set_value();
  pool.shutdown();
  EXPECT_FALSE(running.shed.load());
}

}  // namespace
}  // namespace ganzfeld::serve
