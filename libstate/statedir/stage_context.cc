#include "statedir/stage_context.h"

#include "statedir/stored_problem.h"
#include "statedir/stored_scene.h"
#include "util/error.h"

namespace hapstate {

StageContext open_stage_context(const std::filesystem::path& state, StateAccess access) {
  StateDir dir{state};
  const bool write = access == StateAccess::kWrite;
  std::unique_ptr<StateDirLock> lock;
  if (write && std::filesystem::exists(dir.catalogue())) lock = std::make_unique<StateDirLock>(dir);
  Catalogue catalogue =
      open_imported_catalogue(dir, write ? OpenMode::kMigrate : OpenMode::kReadOnly);
  SceneRecord record = read_stored_scene(catalogue, dir);
  const StageRun import = require_stage_run(catalogue, dir, "import");
  const std::optional<ContentHash> expected = run_input(import, "problem");
  if (!expected) {
    throw InputError(dir.catalogue().string() +
                     ": the import run records no problem hash "
                     "(damaged?): re-import with --fresh");
  }
  const std::string label = dir.catalogue().string() + " (stored scene)";
  Scene scene = parse_stored_scene(record, dir);
  Problem problem = load_stored_problem(dir, scene, *expected);
  GridSpec grid = resolve_grid(scene.grid, problem.probe_rest, label, problem.probe_sag);
  return StageContext{dir,
                      std::move(lock),
                      std::move(catalogue),
                      std::move(record),
                      std::move(scene),
                      std::move(problem),
                      *expected,
                      grid};
}

}  // namespace hapstate
