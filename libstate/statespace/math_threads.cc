#include "statespace/math_threads.h"

#include <dlfcn.h>

#include <cstdlib>
#include <initializer_list>

namespace hapstate {

void limit_math_threads() {
  for (const char* name : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                           "BLIS_NUM_THREADS", "GOTO_NUM_THREADS"}) {
    ::setenv(name, "1", 1);
  }
  using SetThreads = void (*)(int);
  for (const char* symbol : {"openblas_set_num_threads", "omp_set_num_threads"}) {
    if (void* f = ::dlsym(RTLD_DEFAULT, symbol)) reinterpret_cast<SetThreads>(f)(1);
  }
}

}  // namespace hapstate
