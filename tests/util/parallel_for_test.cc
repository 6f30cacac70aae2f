#include "util/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace calibench {
namespace {

// Every index exactly once, whatever the thread count (including more threads than items).
TEST(ParallelFor, CallsEveryIndexExactlyOnce) {
  for (int threads : {1, 2, 3, 8}) {
    for (size_t n : {size_t{0}, size_t{1}, size_t{5}, size_t{1000}}) {
      std::vector<std::atomic<int>> calls(n);
      ParallelFor(n, threads, [&](int, size_t i) { ++calls[i]; });
      for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(calls[i].load(), 1) << "index " << i << ", n " << n << ", threads " << threads;
      }
    }
  }
}

// Worker ids lie in [0, ParallelWorkers) and the caller's thread is worker 0.
TEST(ParallelFor, WorkersAreNumberedFromTheCallingThread) {
  EXPECT_EQ(ParallelWorkers(4, 2), 2);
  EXPECT_EQ(ParallelWorkers(4, 100), 4);
  EXPECT_EQ(ParallelWorkers(3, 0), 1);
  EXPECT_GE(ParallelWorkers(0, 100), 1);  // The hardware's concurrency.
  const std::thread::id caller = std::this_thread::get_id();
  std::mutex mutex;
  std::set<int> seen;
  bool worker0_is_caller = true;
  ParallelFor(200, 3, [&](int worker, size_t) {
    std::lock_guard<std::mutex> lock(mutex);
    seen.insert(worker);
    if (worker == 0 && std::this_thread::get_id() != caller) worker0_is_caller = false;
  });
  EXPECT_TRUE(worker0_is_caller);
  // spawn_every_worker: no call on the calling thread.
  bool caller_ran = false;
  ParallelForOptions spawned;
  spawned.threads = 2;
  spawned.spawn_every_worker = true;
  ParallelFor(50, spawned, [&](int, size_t) {
    std::lock_guard<std::mutex> lock(mutex);
    if (std::this_thread::get_id() == caller) caller_ran = true;
  });
  EXPECT_FALSE(caller_ran);
  for (int w : seen) {
    EXPECT_GE(w, 0);
    EXPECT_LT(w, 3);
  }
}

// Indices start in increasing order: when index i starts, every smaller index has started
// (the harness relies on it to commit rows in order with a bounded buffer).
TEST(ParallelFor, IndicesStartInOrder) {
  std::mutex mutex;
  std::vector<size_t> starts;
  ParallelFor(500, 4, [&](int, size_t i) {
    std::lock_guard<std::mutex> lock(mutex);
    starts.push_back(i);
  });
  ASSERT_EQ(starts.size(), 500u);
  // Logged under the same lock right after the index is taken, so each start may be overtaken by
  // at most (workers - 1) later indices.
  for (size_t k = 0; k < starts.size(); ++k) {
    EXPECT_LE(starts[k], k + 3) << "position " << k;
  }
}

// A body whose result depends only on the index gives the same results for every thread count.
TEST(ParallelFor, ResultsDoNotDependOnTheThreadCount) {
  auto run = [](int threads) {
    std::vector<uint64_t> out(300);
    ParallelFor(out.size(), threads, [&](int, size_t i) {
      uint64_t x = i * 0x9E3779B97F4A7C15ull;
      for (int r = 0; r < 100; ++r) x ^= x << 13, x ^= x >> 7, x ^= x << 17;
      out[i] = x;
    });
    return out;
  };
  const std::vector<uint64_t> one = run(1);
  EXPECT_EQ(run(2), one);
  EXPECT_EQ(run(5), one);
}

}  // namespace
}  // namespace calibench
