// The import stage (hapstate-import): a scene and its mesh into a state directory.
#pragma once

#include "statedir/stage_run.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

struct ImportOptions {
  std::filesystem::path scene;  // scene.toml
  std::filesystem::path state;  // state directory (created if missing)
  bool fresh = false;           // replace the state directory's contents (after validation)

  // Throws InputError naming the first missing option (run_import calls it first).
  void check() const;
};

// What an import that did something (outcome kOk) did.
enum class ImportChange {
  kCreated,    // new state directory
  kUpdated,    // allowed changes recorded (max_force, enlarged workspace, scene text)
  kRecreated,  // --fresh: the old contents were deleted, the scene imported anew
};

// outcome kOk or kUnchanged (the same scene was imported before: nothing done); warnings: mesh
// repairs and the like.
struct ImportReport : StageReport {
  ImportChange change = ImportChange::kCreated;
};

// Validates the scene and mesh (build_problem, grid alignment) before touching the state
// directory, then:
// - new directory (or one without an imported scene): creates catalogue.sqlite, blobs/ and
//   problem/ (mesh + constraints), records the scene and an "import" stage run;
// - same scene as recorded: records an "unchanged" run, nothing else;
// - only probe.max_force, the scene text or an enlarged workspace differ: records the new
//   scene text and a run; keeps every configuration;
// - anything else differs (mesh, material, constraints, solver, levels, spacing, probe mode, a
//   workspace that no longer holds every check-point): InputError naming what changed and
//   that --fresh starts over. With `fresh`, the directory's state files are deleted and the
//   scene imported anew (only after the validation succeeded).
// Throws InputError for a bad scene or mesh, or a state directory that cannot be used (a
// catalogue of another application or of a newer hapstate); nothing is changed then.
ImportReport run_import(const ImportOptions& options);

}  // namespace hapstate
