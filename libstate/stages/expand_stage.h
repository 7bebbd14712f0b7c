// The expand stage (hapstate-expand): breadth-first waves of transitions from the zero
// configuration (docs/state-space.md).
#pragma once

#include "catalogue/records.h"
#include "solver/path_solver.h"
#include "statedir/stage_run.h"
#include "statespace/expand_batch.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace hapstate {

struct ExpandOptions {
  std::filesystem::path state;
  int threads = 1;                           // worker threads, one PathSolver each
  int batch_size = 32;                       // transitions per batch (one segment, one transaction)
  std::optional<long long> max_transitions;  // stop at the first batch boundary at or past it
  std::optional<double> max_seconds;         // stop at the first batch boundary past it
  std::FILE* progress = stderr;              // progress line; nullptr: none
  SolverAlgorithm algorithm = SolverAlgorithm::kFast;  // kReference: the paper's (comparisons)
  TransitionEngineFactory engine;                      // empty: threads in this process

  // Throws InputError naming the first option out of range (run_expand calls it first).
  void check() const;
};

// outcome: kOk (nothing undecided left), kPartial (a limit or a stop request), kUnchanged.
struct ExpandReport : StageReport {
  long long decided = 0;  // transitions decided in this run
  long long solved = 0;   // of which solved (reached or failed)
  long long trivial = 0;  // of the solved: contact moves between free check-points at
                          // rest, recorded without a solve
  long long failed = 0;
  long long factorisations = 0;  // numeric factorisations of this run's solved transitions
  long long outside = 0;
  long long new_configurations = 0;
  long long reused_levels = 0;       // reached an existing level
  long long expandable_changed = 0;  // configurations whose expandable flag changed (F_max)
  std::size_t garbage_segments = 0;  // unreferenced segments removed at start
  // Where the time went (this run; the whole stage's is wall_s): the parallel solves and
  // deciding + storing batches (level comparison, segment write + fsync, catalogue commit);
  // `solver` sums the workers' assembly / factorisation / solve seconds.
  double solve_wall_s = 0, store_wall_s = 0;
  SolverTimings solver;
  std::string engine_summary;  // how the work was shared (MPI: per rank); "" for threads
};

// Runs the expansion until every expandable configuration has all 26 directions decided, or
// a limit is reached or stop_requested() (Ctrl-C, see util/stop_request.h; then outcome
// kPartial). Batches of `batch_size` undecided (source,
// direction) pairs, taken in canonical order (wave, source id, direction), are solved in
// parallel and then decided and stored in that order: new vectors into a new segment that is
// closed (fsynced) before the one catalogue transaction referencing it commits. So the
// catalogue does not depend on the thread count, nor on where a run was killed and resumed.
// Before any change: validates the state directory (imported, grid up to date, every
// referenced segment and vector readable) and throws InputError otherwise. Then removes
// unreferenced segments (left by a crash), marks expand runs a crash left "running" as failed
// ("interrupted"), updates expandable flags to the scene's max_force,
// and records an "expand" stage run. Nothing undecided: records "unchanged" and returns.
ExpandReport run_expand(const ExpandOptions& options);

}  // namespace hapstate
