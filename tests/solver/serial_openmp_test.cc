// SerialOpenMP (solver/serial_openmp.h), what SparseCholesky::factorize holds around CHOLMOD: a
// region asking for 4 threads with a num_threads clause, as CHOLMOD's are, runs on one inside it,
// on every worker thread, and gets its 4 again after it.
#include "solver/serial_openmp.h"
#include "util/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace hapstate {
namespace {

int team_of_four() {
  int n = 0;
#pragma omp parallel num_threads(4)
  {
#pragma omp single
    n = omp_get_num_threads();
  }
  return n;
}

TEST(SerialOpenMP, NoTeamInsideOnAnyWorkerAndTheLimitIsPutBack) {
  std::vector<int> inside(8, -1), after(8, -1);
  std::atomic<int> entered{0};
  parallel_for(inside.size(), 4, [&](std::size_t i, int) {
    // The first four indices wait for each other, so each is on a worker of its own.
    ++entered;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (entered < 4 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    {
      const SerialOpenMP serial;
      inside[i] = team_of_four();
    }
    after[i] = team_of_four();
  });
  for (int n : inside) EXPECT_EQ(n, 1);
  for (int n : after) EXPECT_EQ(n, 4);  // no global change: hapstate-solve's assembly keeps its
}

}  // namespace
}  // namespace hapstate
