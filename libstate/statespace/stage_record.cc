#include "statespace/stage_record.h"

#include "catalogue/transaction.h"
#include "statespace/state_dir.h"

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

void record_unchanged(Catalogue& catalogue, StageRun run, const std::string& message) {
  run.outcome = StageOutcome::kUnchanged;
  run.ended = now_ms();
  run.message = message;
  catalogue.insert_stage_run(run);
}

StageRunId start_stage_run(Catalogue& catalogue, const StageRun& run, int* interrupted) {
  Transaction tx(catalogue);
  for (const StageRun& old : catalogue.read_stage_runs(run.stage)) {
    if (old.outcome != StageOutcome::kRunning) continue;
    catalogue.update_stage_run_end(old.id, StageOutcome::kFailed, now_ms(),
                                   "interrupted: the process ended before finishing (killed?); "
                                   "resumed by a later run");
    if (interrupted) ++*interrupted;
  }
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
