// hapstate-grid: the check-point grid and the zero configuration of an imported state directory.
#include "stages/grid_stage.h"
#include "statespace/math_threads.h"
#include "util/main_guard.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  std::string state;
  CLI::App app{
      "hapstate-grid: create the check-points of the scene's grid (aligned on the probe's rest "
      "position, which is check-point (0,0,0)), classify them and store the zero configuration. "
      "Re-running after the workspace was enlarged adds check-points and keeps the old ones.\n"
      "Exit codes: 0 done or unchanged; 1 internal error; 2 bad options or state directory "
      "(not imported, inconsistent): nothing changed."};
  use_hapstate_help(app);
  app.add_option("--state", state, "state directory (after hapstate-import)")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  return guarded_main("hapstate-grid", [&] {
    const GridReport r = run_grid(GridOptions{state});
    std::printf("hapstate-grid: %s\n", r.message.c_str());
    return kExitOk;
  });
}
