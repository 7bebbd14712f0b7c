#include "util/cores.h"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace hapstate {

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

int ranks_on_this_host() {
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "SLURM_NTASKS_PER_NODE"}) {
    // Read once at start-up, before any thread (NOLINT: the environment is not changed then).
    if (const char* v = std::getenv(name)) {  // NOLINT(concurrency-mt-unsafe)
      const int n = std::atoi(v);
      if (n >= 1) return n;
    }
  }
  return 1;
}

int default_threads() {
  const int ranks = ranks_on_this_host();
  const int cores = usable_cores();
  // Bound to fewer cores than the host has (mpirun --bind-to core): those are this rank's.
  if (ranks > 1 && cores < static_cast<int>(std::thread::hardware_concurrency())) return cores;
  return std::max(1, cores / std::max(1, ranks - 1));
}

}  // namespace hapstate
