// Keeps BLAS/LAPACK and OpenMP (used by CHOLMOD) to one thread per process thread, so a stage
// with N worker threads uses N cores and its results do not depend on the BLAS thread count.
#pragma once

namespace hapstate {

// Sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS, BLIS_NUM_THREADS and
// GOTO_NUM_THREADS to `threads` (overriding the environment) and, for libraries already loaded
// that read the environment only once, calls openblas_set_num_threads / omp_set_num_threads
// when present in the process. Call it before any BLAS call and before starting threads (setenv
// is not thread-safe).
void set_math_threads(int threads);
// set_math_threads(1): first thing in the main() of the stages, whose worker threads each run
// their own solver.
inline void limit_math_threads() { set_math_threads(1); }

}  // namespace hapstate
