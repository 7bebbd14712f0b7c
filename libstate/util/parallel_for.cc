#include "util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace hapstate {

void parallel_for(std::size_t n, int threads,
                  const std::function<void(std::size_t i, int worker)>& body) {
  std::atomic<std::size_t> next{0};
  std::mutex mutex;  // the first error
  std::exception_ptr error;
  auto work = [&](int worker) {
    try {
      for (std::size_t i = next++; i < n; i = next++) body(i, worker);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      next = n;
    }
  };
  const int workers =
      static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(std::max(threads, 1), n)));
  std::vector<std::thread> pool;
  try {
    for (int w = 1; w < workers; ++w) pool.emplace_back(work, w);
  } catch (...) {  // a thread could not start: the started ones finish, then the error goes on
    next = n;
    for (std::thread& t : pool) t.join();
    throw;
  }
  work(0);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace hapstate
