// Work shared by a few threads: each index handed out once, the first error carried back.
#pragma once

#include <cstddef>
#include <functional>

namespace hapstate {

// Runs body(i, worker) for every i in [0, n), each once, in no fixed order, on
// min(threads, n) workers (at least one); the calling thread is worker 0, the others are
// numbered 1, 2, ... (a worker keeps its number, so per-worker state can be indexed by it).
// The first exception a body throws stops the handing out of indices; it is rethrown once every
// worker has ended. A thread that cannot start: the started workers finish, then that error is
// thrown. A body that wants to stop early (a stop request) returns at once for the
// indices left.
void parallel_for(std::size_t n, int threads,
                  const std::function<void(std::size_t i, int worker)>& body);

}  // namespace hapstate
