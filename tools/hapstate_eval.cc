// hapstate-eval: the paper's accuracy experiment on a state directory and its playback file
// (docs/playback.md): precise solves along a random probe path vs. playback, per scheme.
#include "eval/eval_report.h"
#include "eval/evaluation.h"
#include "statespace/math_threads.h"
#include "util/main_guard.h"
#include "util/progress.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <vector>

namespace {

using namespace hapstate;

// hapstate-eval --seeds N: N random paths, the distribution of their largest errors.
int run_seeds(EvalOptions o, int seeds, const std::string& csv) {
  std::vector<EvalResult> runs;
  const std::uint64_t first = o.seed;
  // One progress line over the paths (a log gets one line per 10 s, not two per path).
  Progress progress("hapstate-eval: paths", seeds);
  o.progress = nullptr;
  for (int k = 0; k < seeds; ++k, ++o.seed) {
    runs.push_back(run_eval(o));
    progress.update(k + 1);
  }
  progress.finish();
  const std::filesystem::path csv_file =
      csv.empty() ? o.state / "eval_seeds.csv" : std::filesystem::path(csv);
  write_seeds_csv(runs, first, csv_file);
  std::printf("%s", seeds_table(runs, first).c_str());
  std::printf("per-path errors: %s\n", csv_file.c_str());
  for (const EvalResult& r : runs)
    if (failed_steps(r) > 0) return kExitSolveFailed;
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  limit_math_threads();
  EvalOptions o;
  std::string state, playback, path_file, csv, png;
  bool no_plot = false;
  int seeds = 1;
  CLI::App app{
      "hapstate-eval: solve a seeded random probe path inside the precomputed region precisely "
      "(Newton, step by step from rest) and play it back with each interpolation scheme; print "
      "the relative force error |f - f*| / max|f*| and deformation error ||u - u*|| / ||u*|| per "
      "step, write them as CSV and plot them like the paper's Fig. 2.\n"
      "Exit codes: 0 done; 1 internal error; 2 bad options, state directory or playback file; "
      "3 a precise solve failed (the other steps are still reported)."};
  use_hapstate_help(app);
  app.add_option("--state", state, "state directory (after hapstate-index)")->required();
  app.add_option("--playback", playback,
                 "playback file (default <state>/playback.bin; "
                 "index with --nodes all for the all-node error)");
  app.add_option("--steps", o.steps,
                 "steps of the random path (default 30: seed s is the certificate's path s)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--seed", o.seed, "seed of the random path");
  app.add_option("--seeds", seeds,
                 "random paths with seeds --seed, --seed + 1, ...: print the median, 90th "
                 "percentile and largest of their largest errors, and write one CSV row per path "
                 "(no plot)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--step-length", o.step_length,
                 "length of a step, mesh units (default half the smallest grid spacing)")
      ->check(positive());
  app.add_option("--path", path_file,
                 "probe path CSV (x,y,z) instead of the random path (default: the random path)")
      ->check(CLI::ExistingFile);
  app.add_option("--csv", csv,
                 "per-step CSV (default <state>/eval.csv; with --seeds one row per path, default "
                 "<state>/eval_seeds.csv)");
  app.add_option("--plot", png, "PNG plot (default <state>/eval.png)");
  app.add_flag("--no-plot", no_plot, "do not plot");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  o.state = state;
  o.playback = playback;
  o.path_file = path_file;
  if (seeds > 1 && !path_file.empty()) {
    std::fprintf(stderr, "hapstate-eval: --seeds %d: give either --seeds or --path\n", seeds);
    return kExitBadInput;
  }
  return guarded_main("hapstate-eval", [&] {
    if (seeds > 1) return run_seeds(o, seeds, csv);
    const EvalResult r = run_eval(o);
    const std::filesystem::path csv_file =
        csv.empty() ? o.state / "eval.csv" : std::filesystem::path(csv);
    write_eval_csv(r, csv_file);
    std::printf("%s", eval_table(r).c_str());
    if (r.max_exact_force == 0)
      std::printf(
          "note: the path never loaded the body (max |f*| = 0 N), so the errors measure nothing: "
          "expand further (a contact probe's region ends where the expansion stopped) or give "
          "--path\n");
    std::printf("per-step errors: %s\n", csv_file.c_str());
    if (!no_plot) {
      const std::filesystem::path png_file =
          png.empty() ? o.state / "eval.png" : std::filesystem::path(png);
      char title[160];
      std::snprintf(
          title, sizeof title, "%zu-step %s, grid spacing %.3g, max |f*| %.3g N", r.steps.size(),
          path_file.empty() ? "random path" : std::filesystem::path(path_file).filename().c_str(),
          r.spacing.minCoeff(), r.max_exact_force);
      plot_eval(csv_file, png_file, title);
      std::printf("plot: %s\n", png_file.c_str());
    }
    return failed_steps(r) > 0 ? kExitSolveFailed : kExitOk;
  });
}
