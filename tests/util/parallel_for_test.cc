// parallel_for: every index once, workers numbered from the calling thread, the first error
// carried back and no index handed out after it.
#include "util/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace hapstate {
namespace {

TEST(ParallelFor, EveryIndexOnceOnNumberedWorkers) {
  const std::size_t n = 1000;
  std::vector<std::atomic<int>> calls(n);
  std::mutex mutex;
  std::set<int> workers;
  std::thread::id worker0;
  parallel_for(n, 4, [&](std::size_t i, int worker) {
    ++calls[i];
    std::lock_guard<std::mutex> lock(mutex);
    workers.insert(worker);
    if (worker == 0) worker0 = std::this_thread::get_id();
  });
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(calls[i], 1) << i;
  for (int w : workers) {
    EXPECT_GE(w, 0);
    EXPECT_LT(w, 4);
  }
  if (workers.count(0)) {
    EXPECT_EQ(worker0, std::this_thread::get_id());  // worker 0 is the caller
  }
}

TEST(ParallelFor, NoMoreWorkersThanIndices) {
  std::atomic<int> highest{-1};
  parallel_for(2, 16, [&](std::size_t, int worker) {
    int h = highest;
    while (worker > h && !highest.compare_exchange_weak(h, worker)) {
    }
  });
  EXPECT_LE(highest, 1);
  int calls = 0;
  parallel_for(0, 4, [&](std::size_t, int) { ++calls; });
  EXPECT_EQ(calls, 0);
  parallel_for(3, 0, [&](std::size_t, int worker) { calls += 1 + worker; });  // 0 threads: one
  EXPECT_EQ(calls, 3);
}

TEST(ParallelFor, TheFirstErrorIsRethrownAndStopsTheHandOut) {
  std::vector<std::size_t> seen;
  try {
    parallel_for(100, 1, [&](std::size_t i, int) {
      seen.push_back(i);
      if (i == 3) throw std::runtime_error("index 3 failed");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "index 3 failed");
  }
  EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1, 2, 3}));

  // On several threads the error comes back whichever worker met it.
  EXPECT_THROW(parallel_for(1000, 3,
                            [&](std::size_t i, int) {
                              if (i == 10) throw std::logic_error("ten");
                            }),
               std::logic_error);
}

}  // namespace
}  // namespace hapstate
