// parallel_for: every index once, workers numbered from the calling thread, the first error
// carried back and no index handed out after it.
#include "util/parallel_for.h"

#include "statespace/math_threads.h"
#include "util/openmp_levels.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <chrono>
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

// A stage's workers run CHOLMOD's `parallel for num_threads(4)` on their own thread: after
// set_math_threads(1) in the calling thread, a region asking for 4 threads inside a worker gets
// one (GCC's libgomp would start each new thread with the process's limit, not the caller's).
TEST(ParallelFor, WorkersKeepTheCallersOpenMPLimit) {
  const int before = openmp_active_levels();
  ASSERT_GE(before, 0) << "no OpenMP runtime in the test";
  set_math_threads(1);
  EXPECT_EQ(openmp_active_levels(), 0);
  std::vector<int> team(8, -1);
  std::atomic<int> entered{0};
  parallel_for(team.size(), 4, [&](std::size_t i, int) {
    // The first four indices wait for each other, so each is on a worker of its own.
    ++entered;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (entered < 4 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    int n = 0;
#pragma omp parallel num_threads(4)
    {
#pragma omp single
      n = omp_get_num_threads();
    }
    team[i] = n;
  });
  set_openmp_active_levels(before);
  for (int n : team) EXPECT_EQ(n, 1);
}

}  // namespace
}  // namespace hapstate
