// hapstate-certify: the certificate of a state's playback file (docs/certificate.md).
#include "stages/certify_stage.h"
#include "statespace/math_threads.h"
#include "util/cores.h"
#include "util/main_guard.h"
#include "util/stop_request.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  CertifyOptions options;
  std::string state;
  bool quiet = false;
  CLI::App app{
      "hapstate-certify: after hapstate-index, measure what the playback file promises: the "
      "paper's experiment (precise solver against the Hermite and trilinear cursors) on seeded "
      "random paths over the whole workspace, the largest stored stiffness against common "
      "haptic devices and the haptic query's time. Stores it in the catalogue "
      "(hapstate-inspect summary shows it) and its headline numbers in the playback file. "
      "Resumable: each path is committed whole.\n"
      "Exit codes: 0 done or nothing to do; 1 internal error; 2 bad options, state directory or "
      "playback file; 130 stopped by Ctrl-C or SIGTERM (run again to resume)."};
  use_hapstate_help(app);
  app.add_option("--state", state, "state directory (after hapstate-index)")->required();
  app.add_option("--paths", options.paths,
                 "random paths, seeds 1..N (default: the scene's certify.paths, else 20)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--steps", options.steps,
                 "steps per path (default: the scene's certify.steps, else 30)")
      ->check(CLI::Range(2, 100000));
  options.threads = default_threads();
  app.add_option("--threads", options.threads,
                 "worker threads (default: the cores this process may use, here " +
                     std::to_string(options.threads) + ")")
      ->check(CLI::Range(1, 1024));
  app.add_option("--check-above", options.check_above,
                 "two-sided solves at each cursor's worst step whose force error is above this "
                 "fraction of its path's largest force: the precise solver reaches it from half a "
                 "spacing before and after on each axis, telling a jump of the force (two "
                 "equilibria, which no spacing removes) from a steep ramp (default 0.01; inf: "
                 "never)");
  app.add_flag("-q,--quiet", quiet, "no progress line and no report, only the one-line result");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  options.state = state;
  options.progress = quiet ? nullptr : stderr;
  install_stop_request_handler(
      "\nhapstate-certify: stopping after the paths (or the worst step's two-sided solves) being "
      "solved (Ctrl-C again stops at once; "
      "either way, run the same command again to resume)\n");
  return guarded_main("hapstate-certify", [&] {
    const CertifyReport r = run_certify(options);
    std::printf("hapstate-certify: %s (%.1f s)\n", r.message.c_str(), r.wall_s);
    if (!quiet) std::printf("%s", certificate_text(r.certificate).text.c_str());
    return r.stopped_by_signal ? kExitInterrupted : kExitOk;
  });
}
