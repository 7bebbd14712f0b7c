// Recording stage runs in the catalogue (table stage_run): what a stage consumed and how it
// ended, so a re-run can skip and a user can audit.
#pragma once

#include "catalogue/catalogue.h"
#include "statedir/scene_identity.h"

#include <exception>
#include <string>

namespace hapstate {

// Now, as stored in stage_run (ms since the Unix epoch, UTC).
TimeMs now_ms();

// A StageRun row with the given inputs (sorted by name) and parameters, started now, outcome
// kRunning (not inserted).
StageRun make_stage_run(const std::string& stage, NamedHashes inputs,
                        const std::string& parameters);

// The one way a stage records that it had nothing to do: `run` inserted as ended now with
// outcome kUnchanged and `message`, in one transaction with closing the runs of the same stage
// a crash left "running" (as start_stage_run: a run killed after it had done all its work
// leaves nothing to do, and its row must not stay "running").
void record_unchanged(Catalogue& catalogue, StageRun run, const std::string& message);

// Starts recording `run` (inserted as running) in one transaction with closing the runs of the
// same stage a crash left "running" (marked failed, "interrupted: ..."; the caller holds the
// directory's lock, so they are not running). Returns its id; `*interrupted` counts those closed.
StageRunId start_stage_run(Catalogue& catalogue, const StageRun& run, int* interrupted = nullptr);

// The scope of a stage run recorded while it works (expand, compact): runs body() for the run
// `id` already inserted as running, and returns what it returns. The body records the normal
// end; if it throws, the run is
// recorded as failed with the exception's message (best effort: a catalogue that cannot be
// written is not hidden behind a second error) and the exception goes on.
template <typename Body>
auto with_run_record(Catalogue& catalogue, StageRunId id, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const std::exception& e) {
    try {
      catalogue.update_stage_run_end(id, StageOutcome::kFailed, now_ms(), e.what());
    } catch (...) {
    }
    throw;
  }
}

// Whether `a` and `b` record the same hash for every name in `names`.
bool same_inputs(const StageRun& a, const NamedHashes& b, const std::vector<std::string>& names);

}  // namespace hapstate
