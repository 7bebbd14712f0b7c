// No OpenMP team inside a CHOLMOD factorisation. CHOLMOD's supernodal factorisation (SuiteSparse
// 5, Debian 12) clears and copies its workspace in `#pragma omp parallel for num_threads(4)`
// loops; a num_threads clause overrides OMP_NUM_THREADS and omp_set_num_threads, so every
// factorisation of every solver woke a team of 4 threads, however many solvers ran side by side
// (each stage runs one per core). Only a limit of zero active parallel levels stops such a
// clause; libgomp keeps that limit per thread, so it is set around the call, on the calling
// thread, and put back after (docs/benchmarks.md, "CHOLMOD's own threads").
#pragma once

#include <omp.h>

namespace hapstate {

class SerialOpenMP {
 public:
  SerialOpenMP() : saved_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMP() { omp_set_max_active_levels(saved_); }
  SerialOpenMP(const SerialOpenMP&) = delete;
  SerialOpenMP& operator=(const SerialOpenMP&) = delete;

 private:
  int saved_;
};

}  // namespace hapstate
