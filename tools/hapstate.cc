// hapstate: the one-command driver. `hapstate run SCENE` runs the precomputation stages in order
// (import -> grid -> expand -> refine -> compact -> index -> certify) on the scene's state
// directory; every
// stage skips the work whose inputs have not changed, so re-running does only what is out of date.
#include "maintenance/compact.h"
#include "stages/certify_stage.h"
#include "stages/expand_stage.h"
#include "stages/grid_stage.h"
#include "stages/import_stage.h"
#include "stages/index_stage.h"
#include "stages/refine_stage.h"
#include "statespace/math_threads.h"
#include "util/cores.h"
#include "util/main_guard.h"
#include "util/stop_request.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace hapstate {
namespace {

struct RunOptions {
  std::string scene;
  std::string state;  // default: "state" beside the scene file
  int threads = 1;
  std::optional<double> max_seconds;
  bool fresh = false;
  bool no_refine = false;
  bool no_compact = false;
  bool no_certify = false;
  ViewNodes view = ViewNodes::kAll;
  bool quiet = false;
};

int stopped() {
  std::printf("hapstate run: stopped; run the same command again to resume\n");
  return kExitInterrupted;
}

int run_pipeline(const RunOptions& o) {
  const std::filesystem::path scene = o.scene;
  const std::filesystem::path state =
      o.state.empty() ? scene.parent_path() / "state" : std::filesystem::path(o.state);
  std::printf("hapstate run: scene %s, state directory %s\n", scene.c_str(), state.c_str());

  const ImportReport imported = run_import(ImportOptions{scene, state, o.fresh});
  for (const auto& w : imported.warnings)
    std::fprintf(stderr, "hapstate run: import: warning: %s\n", w.c_str());
  std::printf("  import:  %s\n", imported.message.c_str());

  if (stop_requested()) return stopped();
  std::printf("  grid:    %s\n", run_grid(GridOptions{state}).message.c_str());
  if (stop_requested()) return stopped();

  ExpandOptions expand;
  expand.state = state;
  expand.threads = o.threads;
  expand.max_seconds = o.max_seconds;
  expand.progress = o.quiet ? nullptr : stderr;
  const ExpandReport expanded = run_expand(expand);
  std::printf("  expand:  %s\n", expanded.message.c_str());
  if (expanded.stopped_by_signal) return stopped();
  if (expanded.outcome == StageOutcome::kPartial) {
    std::printf("hapstate run: expansion stopped at --max-seconds; run again to continue\n");
    return kExitOk;
  }
  if (stop_requested()) return stopped();
  if (!o.no_refine) {
    RefineOptions refine;
    refine.state = state;
    refine.threads = o.threads;
    refine.progress = o.quiet ? nullptr : stderr;
    const RefineReport refined = run_refine(refine);
    std::printf("  refine:  %s\n", refined.message.c_str());
    if (refined.stopped_by_signal) return stopped();
  }
  if (stop_requested()) return stopped();
  if (!o.no_compact) {
    CompactOptions compact;
    compact.state = state;
    std::printf("  compact: %s\n", run_compact(compact).headline().c_str());
  }
  if (stop_requested()) return stopped();
  IndexOptions index;
  index.state = state;
  index.view = o.view;
  index.progress = o.quiet ? nullptr : stderr;
  std::printf("  index:   %s\n", run_index(index).message.c_str());
  if (o.no_certify) return kExitOk;
  if (stop_requested()) return stopped();
  CertifyOptions certify;
  certify.state = state;
  certify.threads = o.threads;
  certify.progress = o.quiet ? nullptr : stderr;
  const CertifyReport certified = run_certify(certify);
  std::printf("  certify: %s\n", certified.message.c_str());
  if (certified.stopped_by_signal) return stopped();
  if (!o.quiet) std::printf("  %s", certificate_text(certified.certificate).headline.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace hapstate

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // stage lines and the progress line in order
  RunOptions o;
  CLI::App app{
      "hapstate: the precomputation in one command. See docs/state-space.md.\n"
      "Exit codes: 0 ok (or stopped at --max-seconds); 1 internal error; 130 stopped by Ctrl-C "
      "or SIGTERM (resumable); 2 bad scene, "
      "mesh or state directory (the stage that found it changed nothing)."};
  use_hapstate_help(app, true);
  app.require_subcommand(1);
  CLI::App* run = app.add_subcommand("run",
                                     "import -> grid -> expand -> refine -> compact -> index -> "
                                     "certify; each stage skips what is up to date");
  run->add_option("scene", o.scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("--state", o.state, "state directory (default: 'state' beside the scene)");
  o.threads = default_threads();
  run->add_option("--threads", o.threads,
                  "expansion, refinement and certificate worker threads (default: the cores this "
                  "process may "
                  "use, here " +
                      std::to_string(o.threads) + ")")
      ->check(CLI::Range(1, 1024));
  run->add_option("--max-seconds", o.max_seconds,
                  "stop the expansion cleanly after about this long (resume by running again; "
                  "default: no limit)")
      ->check(positive());
  run->add_flag("--fresh", o.fresh, "start the state directory anew (after validating the scene)");
  run->add_flag("--no-refine", o.no_refine,
                "skip the refine stage (faster; cells an earlier run refined are still played "
                "back refined; a contact scene refines every touched cell: docs/contact.md)");
  run->add_flag("--no-compact", o.no_compact, "skip the compaction stage");
  run->add_flag("--no-certify", o.no_certify,
                "skip the certificate (hapstate-certify: the accuracy experiment on the scene's "
                "certify.paths random paths)");
  run->add_option("--nodes", o.view,
                  "index: store the displacements of all nodes (default; hapstate-eval's "
                  "deformation error needs them) or of the surface nodes only (a smaller file "
                  "for a renderer)")
      ->option_text(choices({"all", "surface"}))
      ->transform(CLI::CheckedTransformer(std::map<std::string, ViewNodes>{
          {"surface", ViewNodes::kSurface}, {"all", ViewNodes::kAll}}));
  run->add_flag("-q,--quiet", o.quiet, "no progress line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return exit_after_parse_error(app, e, "hapstate");
  }
  install_stop_request_handler(
      "\nhapstate run: stopping after the current step (Ctrl-C again stops at once; either way, "
      "run the same command again to resume)\n");
  return guarded_main("hapstate", [&] { return run_pipeline(o); });
}
