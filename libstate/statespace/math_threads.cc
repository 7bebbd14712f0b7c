#include "statespace/math_threads.h"

#include <dlfcn.h>

#include <cstdlib>
#include <initializer_list>
#include <string>

namespace hapstate {

void set_math_threads(int threads) {
  const std::string value = std::to_string(threads < 1 ? 1 : threads);
  for (const char* name : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                           "BLIS_NUM_THREADS", "GOTO_NUM_THREADS"}) {
    // Called by main() before any thread starts (math_threads.h): nothing reads the
    // environment at the same time.
    // NOLINTNEXTLINE(concurrency-mt-unsafe)
    ::setenv(name, value.c_str(), 1);
  }
  using SetThreads = void (*)(int);
  for (const char* symbol : {"openblas_set_num_threads", "omp_set_num_threads"}) {
    if (void* f = ::dlsym(RTLD_DEFAULT, symbol))
      reinterpret_cast<SetThreads>(f)(threads < 1 ? 1 : threads);
  }
}

}  // namespace hapstate
