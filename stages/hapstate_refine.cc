// hapstate-refine: the quarter-spacing points of the cells the half-spacing data do not resolve
// (docs/state-space.md, "Refined cells").
#include "stages/refine_stage.h"
#include "statespace/math_threads.h"
#include "util/cores.h"
#include "util/main_guard.h"
#include "util/stop_request.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>
#include <string>

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  RefineOptions options;
  std::string state;
  std::optional<double> tolerance;
  std::optional<int> depth;
  bool quiet = false;
  CLI::App app{
      "hapstate-refine: after hapstate-expand, solve the force and haptic stiffness at the "
      "quarter-spacing (and eighth-spacing) points of every cell whose estimated interpolation "
      "error exceeds the "
      "tolerance (grab or contact probe). Resumable: each refined cell is committed whole.\n"
      "Exit codes: 0 done or nothing to do; 1 internal error; 2 bad options or state directory; "
      "130 stopped by Ctrl-C or SIGTERM (run again to resume)."};
  use_hapstate_help(app);
  app.add_option("--state", state, "state directory (after hapstate-expand)")->required();
  options.threads = default_threads();
  app.add_option("--threads", options.threads,
                 "worker threads (default: the cores this process may use, here " +
                     std::to_string(options.threads) + ")")
      ->check(CLI::Range(1, 1024));
  app.add_option("--tolerance", tolerance,
                 "refine a cell whose estimated error exceeds this fraction of its largest force "
                 "(default: the scene's grid.refine_tolerance, else 1e-3)")
      ->check(positive());
  app.add_option("--depth", depth,
                 "1: solve a flagged cell's quarter-spacing points; 2: also its eighth-spacing "
                 "ones; 3: also the sixteenth-spacing points of its eighth cells above 10 x the "
                 "tolerance (default: the scene's grid.refine_depth, else for a contact sphere 3 "
                 "where the grid spacing exceeds 0.4 x its radius, 2 where it exceeds 0.1 x, 1 "
                 "otherwise and for the grab probe)")
      ->check(CLI::Range(1, 3));
  app.add_flag("-q,--quiet", quiet, "no progress line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  options.state = state;
  options.tolerance = tolerance;
  options.depth = depth;
  options.progress = quiet ? nullptr : stderr;
  install_stop_request_handler(
      "\nhapstate-refine: stopping after the current cell (Ctrl-C again stops at once; either "
      "way, run the same command again to resume)\n");
  return guarded_main("hapstate-refine", [&] {
    const RefineReport r = run_refine(options);
    std::printf("hapstate-refine: %s (%.1f s)\n", r.message.c_str(), r.wall_s);
    return r.stopped_by_signal ? kExitInterrupted : kExitOk;
  });
}
