// The expand stage over MPI (docs/distributed.md). Rank 0 runs the stage as without MPI: it
// alone opens the state directory, decides and stores every batch in the canonical order, so
// the catalogue is the one a single thread would write. It hands the wave's transitions to the
// worker ranks dynamically (each worker holds at most two chunks of `threads` tasks: it starts
// the next while its results travel), with the source configuration's vectors inside the task
// and the results coming back as messages: no shared file system is needed.
#pragma once

#include "distributed/mpi_session.h"
#include "statespace/expand_batch.h"

namespace hapstate {

// For the expand stage's ExpandOptions::engine on rank 0 of a distributed session: ranks 1 ..
// size-1 solve, each with `threads` threads (one PathSolver each).
TransitionEngineFactory mpi_engine_factory(const MpiSession& session, int threads,
                                           SolverAlgorithm algorithm);

// Rank 0, once the stage ended (normally or by an exception, engine made or not): tells every
// worker still waiting to stop, so that every rank reaches MPI_Finalize.
void release_mpi_workers(const MpiSession& session);

// Ranks > 0: builds the solvers from the coordinator's set-up, then solves the chunks it sends
// until it says stop. An exception while working is sent to the coordinator (which ends the
// stage with it); the worker then waits for the stop.
void run_mpi_worker();

}  // namespace hapstate
