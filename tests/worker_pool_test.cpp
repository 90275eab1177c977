// serve/worker_pool.h: at most `threads` tasks run at once and `max_waiting` wait; one more is
// refused (the connection loop answers it 503). tests/serve_hostile_test.py checks the same
// through real sockets.
#include <atomic>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "serve/worker_pool.h"

namespace ganzfeld::serve {
namespace {

TEST(WorkerPool, RefusesOnlyBeyondThreadsAndQueue) {
  constexpr std::size_t kThreads = 2, kWaiting = 1;
  std::promise<void> release;
  const std::shared_future<void> released = release.get_future().share();
  WorkerPool pool(kThreads, kWaiting);
  std::promise<void> started[kThreads];
  for (std::size_t k = 0; k < kThreads; ++k) {
    ASSERT_TRUE(pool.try_submit([&, k] {
      started[k].set_value();
      released.wait();
    }));
    started[k].get_future().wait();  // a thread holds it
  }
  std::atomic<int> waited_ran{0};
  EXPECT_TRUE(pool.try_submit([&] { ++waited_ran; }));  // waits: every thread busy, the queue has room
  EXPECT_FALSE(pool.try_submit([] { ADD_FAILURE() << "a refused task ran"; }));
  const WorkerPool::Stats s = pool.stats();
  EXPECT_EQ(s.running, kThreads);
  EXPECT_EQ(s.waiting, kWaiting);
  EXPECT_EQ(s.refused, 1);
  EXPECT_EQ(waited_ran.load(), 0);
  release.set_value();
  pool.shutdown();  // runs what waits, then joins
  EXPECT_EQ(waited_ran.load(), 1);
  EXPECT_FALSE(pool.try_submit([] {})) << "after shutdown";
}

TEST(WorkerPool, ZeroQueueRefusesWhenEveryThreadIsBusy) {
  std::promise<void> release, started;
  WorkerPool pool(1, 0);
  const std::shared_future<void> released = release.get_future().share();
  ASSERT_TRUE(pool.try_submit([&] {
    started.set_value();
    released.wait();
  }));
  started.get_future().wait();
  EXPECT_FALSE(pool.try_submit([] {}));
  release.set_value();
  pool.shutdown();
}

}  // namespace
}  // namespace ganzfeld::serve
