#include "util/openmp_levels.h"

#include <dlfcn.h>

namespace hapstate {

// Looked up at run time, as statespace/math_threads.cc does for OpenBLAS: util links no OpenMP
// runtime, and a process without one has nothing to limit.
int openmp_active_levels() {
  using Get = int (*)();
  void* f = ::dlsym(RTLD_DEFAULT, "omp_get_max_active_levels");
  return f ? reinterpret_cast<Get>(f)() : -1;
}

void set_openmp_active_levels(int levels) {
  if (levels < 0) return;
  using Set = void (*)(int);
  if (void* f = ::dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))
    reinterpret_cast<Set>(f)(levels);
}

}  // namespace hapstate
