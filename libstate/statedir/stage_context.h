// What a stage (grid, expand, refine, index, certify) or a reader (hapstate-eval) loads from an
// imported state directory: the stored scene, the stored problem (verified against the import's
// record) and the resolved grid.
#pragma once

#include "catalogue/catalogue.h"
#include "problem/problem.h"
#include "scene/grid_spec.h"
#include "scene/scene.h"
#include "statedir/state_dir.h"

#include <memory>

namespace hapstate {

struct StageContext {
  StateDir dir;
  std::unique_ptr<StateDirLock> lock;  // held for the whole stage (none for a reader)
  Catalogue catalogue;
  SceneRecord scene_record;
  Scene scene;      // parsed from the stored text (files not re-read)
  Problem problem;  // from problem/ (mesh + constraints) and the stored scene
  ContentHash problem_hash;
  GridSpec grid;
};

// How a state directory is opened: by a stage that writes it (under the directory's lock, the
// catalogue read-write and migrated to the current schema), or by a reader (hapstate-eval: no
// lock, so it runs beside a stage; the catalogue read-only, at the current schema).
enum class StateAccess { kWrite, kRead };

// Locks the directory (StateDirLock; kWrite only), opens the catalogue, re-parses the stored
// scene and loads the stored problem.
// Throws InputError if the directory is not an imported state directory or anything stored
// is inconsistent.
StageContext open_stage_context(const std::filesystem::path& state,
                                StateAccess access = StateAccess::kWrite);

}  // namespace hapstate
