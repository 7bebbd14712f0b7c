#include "statedir/stage_run.h"

#include "catalogue/transaction.h"
#include "statedir/state_dir.h"

#include <algorithm>

namespace hapstate {

TimeMs now_ms() { return std::chrono::time_point_cast<std::chrono::milliseconds>(Clock::now()); }

StageRun make_stage_run(const std::string& stage, NamedHashes inputs,
                        const std::string& parameters) {
  std::sort(inputs.begin(), inputs.end());
  StageRun run;
  run.stage = stage;
  run.inputs = std::move(inputs);
  run.parameters = parameters;
  run.started = now_ms();
  run.outcome = StageOutcome::kRunning;
  return run;
}

namespace {

// Marks the runs of `stage` a crash left "running" failed (the caller holds the directory's
// lock, so none is running); returns how many.
int close_interrupted_runs(Catalogue& catalogue, const std::string& stage) {
  int closed = 0;
  for (const StageRun& old : catalogue.read_stage_runs(stage)) {
    if (old.outcome != StageOutcome::kRunning) continue;
    catalogue.update_stage_run_end(old.id, StageOutcome::kFailed, now_ms(),
                                   "interrupted: the process ended before finishing (killed?); "
                                   "resumed by a later run");
    ++closed;
  }
  return closed;
}

}  // namespace

void record_unchanged(Catalogue& catalogue, StageRun run, const std::string& message) {
  Transaction tx(catalogue);
  close_interrupted_runs(catalogue, run.stage);
  run.outcome = StageOutcome::kUnchanged;
  run.ended = now_ms();
  run.message = message;
  catalogue.insert_stage_run(run);
  tx.commit();
}

StageRunId start_stage_run(Catalogue& catalogue, const StageRun& run, int* interrupted) {
  Transaction tx(catalogue);
  const int closed = close_interrupted_runs(catalogue, run.stage);
  if (interrupted) *interrupted += closed;
  const StageRunId id = catalogue.insert_stage_run(run);
  tx.commit();
  return id;
}

bool same_inputs(const StageRun& a, const NamedHashes& b, const std::vector<std::string>& names) {
  for (const auto& name : names) {
    std::optional<ContentHash> hb;
    for (const auto& [n, h] : b)
      if (n == name) hb = h;
    if (run_input(a, name) != hb) return false;
  }
  return true;
}

}  // namespace hapstate
