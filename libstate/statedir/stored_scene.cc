#include "statedir/stored_scene.h"

#include "util/error.h"

namespace hapstate {

SceneRecord read_stored_scene(Catalogue& catalogue, const StateDir& dir) {
  std::optional<SceneRecord> record = catalogue.read_scene();
  if (!record)
    throw InputError(dir.catalogue().string() + ": no scene stored (run hapstate-import first)");
  return std::move(*record);
}

Scene parse_stored_scene(const SceneRecord& record, const StateDir& dir, bool require_probe) {
  SceneParseOptions options;
  options.check_files = false;
  options.require_probe = require_probe;
  return parse_scene(record.text, dir.catalogue(), options);
}

}  // namespace hapstate
