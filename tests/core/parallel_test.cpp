// parallel_for, the project's one thread pool: every index exactly once with a valid worker index,
// the cap on workers, and a throwing body reaching the caller as its exception (not std::terminate).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/parallel.hpp"

namespace splatcl {
namespace {

TEST(ParallelFor, EveryIndexOnceWithAWorkerIndexBelowTheWorkerCount) {
  for (const std::size_t n : {0u, 1u, 7u, 1000u, 100003u})
    for (const std::size_t block : {1u, 3u, 256u}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << ", block " << block);
      std::vector<std::atomic<int>> seen(n);
      const std::size_t workers = worker_count(n, block);
      std::atomic<bool> bad_worker{false};
      parallel_for(n, block, [&](std::size_t i, std::size_t w) {
        seen[i].fetch_add(1);
        if (w >= workers) bad_worker = true;
      });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i].load(), 1) << "index " << i;
      EXPECT_FALSE(bad_worker.load());
      EXPECT_GE(workers, 1u);
      EXPECT_LE(workers, std::max<std::size_t>(1, (n + block - 1) / block));
      EXPECT_LE(workers, std::max(1u, usable_cpus()));
    }
}

TEST(ParallelFor, MaxWorkersCapsTheWorkerIndex) {
  EXPECT_EQ(worker_count(1000, 1, 1), 1u);
  std::atomic<std::size_t> highest{0};
  parallel_for(
      1000, 1,
      [&](std::size_t, std::size_t w) {
        for (std::size_t h = highest; w > h && !highest.compare_exchange_weak(h, w);) {
        }
      },
      1);
  EXPECT_EQ(highest.load(), 0u);
}

TEST(ParallelFor, AThrowingBodyStopsTheLoopAndReachesTheCaller) {
  for (const std::size_t block : {1u, 64u}) {
    std::atomic<std::size_t> ran{0};
    try {
      // Each other item takes 20 us, so that the rest of the loop (2 s on one thread) outlasts the
      // throw's unwinding, which under ASan on a loaded machine took long enough for the other
      // thread to finish all 100,000 trivial items (a flaky failure in a CI run).
      parallel_for(100000, block, [&](std::size_t i, std::size_t) {
        ran.fetch_add(1);
        if (i == 500) throw std::runtime_error("index 500 failed");
        std::this_thread::sleep_for(std::chrono::microseconds(20));
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "index 500 failed");
    }
    EXPECT_LT(ran.load(), 100000u) << "the hand-out stops after the failure";
  }
  // Run again afterwards: nothing of the failed loop is left behind.
  std::atomic<std::size_t> count{0};
  parallel_for(1000, 7, [&](std::size_t, std::size_t) { count.fetch_add(1); });
  EXPECT_EQ(count.load(), 1000u);
}

}  // namespace
}  // namespace splatcl
