// hapstate-import: a scene and its mesh into a state directory.
#include "stages/import_stage.h"
#include "statespace/math_threads.h"
#include "util/main_guard.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  ImportOptions o;
  std::string scene, state;
  CLI::App app{
      "hapstate-import: validate a scene and its mesh and record them in a state directory "
      "(catalogue.sqlite, blobs/, problem/). Re-importing the same scene does nothing; only "
      "probe.max_force and an enlarged grid.box may change in an existing state directory.\n"
      "Exit codes: 0 imported, updated or unchanged; 1 internal error; 2 bad scene, mesh, "
      "options or state directory (e.g. a state directory of another scene without --fresh): "
      "nothing changed."};
  use_hapstate_help(app);
  app.add_option("scene", scene, "scene file (TOML)")->required();
  app.add_option("--state", state, "state directory (created if missing)")->required();
  app.add_flag("--fresh", o.fresh,
               "delete the state directory's configurations and import anew (after the scene "
               "and mesh validated)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  return guarded_main("hapstate-import", [&] {
    o.scene = scene;
    o.state = state;
    const ImportReport r = run_import(o);
    for (const auto& w : r.warnings)
      std::fprintf(stderr, "hapstate-import: warning: %s\n", w.c_str());
    std::printf("hapstate-import: %s\n", r.message.c_str());
    return kExitOk;
  });
}
