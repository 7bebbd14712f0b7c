// The OpenMP runtime's limit on active parallel levels, per thread. A stage runs one solver per
// worker thread and wants no OpenMP team inside them, but CHOLMOD's supernodal factorisation
// (SuiteSparse 5) asks for 4 threads with a num_threads clause, which overrides OMP_NUM_THREADS
// and omp_set_num_threads; only max-active-levels 0 keeps it on the calling thread
// (statespace/math_threads.h sets it). GCC's libgomp keeps that limit per thread and starts a new
// std::thread with the process's initial value, not its creator's, so whoever starts worker
// threads passes the creator's on (util/parallel_for.h does).
#pragma once

namespace hapstate {

// The calling thread's max-active-levels; -1 where no OpenMP runtime is in the process.
int openmp_active_levels();
// Sets the calling thread's max-active-levels; nothing where levels < 0 or no runtime is loaded.
void set_openmp_active_levels(int levels);

}  // namespace hapstate
