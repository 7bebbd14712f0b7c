// Recording stage runs in the catalogue (table stage_run): what a stage consumed and how it
// ended, so a re-run can skip and a user can audit.
#pragma once

#include "catalogue/catalogue.h"
#include "statespace/scene_identity.h"

#include <string>

namespace hapstate {

// Now, as stored in stage_run (ms since the Unix epoch, UTC).
TimeMs now_ms();

// A StageRun row with the given inputs (sorted by name) and parameters, started now, outcome
// kRunning (not inserted).
StageRun make_stage_run(const std::string& stage, NamedHashes inputs, const std::string& parameters);

// Whether `a` and `b` record the same hash for every name in `names`.
bool same_inputs(const StageRun& a, const NamedHashes& b, const std::vector<std::string>& names);

}  // namespace hapstate
