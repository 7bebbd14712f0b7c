// hapstate-stress: the numerical stress suite (eval/stress_case.h, docs/benchmarks.md): the
// precise path solver over law x nu x load x step x mesh quality x probe; a CSV row and a
// Markdown line per case, success rates and the failures with reasons.
#include "eval/stress_case.h"
#include "eval/stress_report.h"
#include "statespace/math_threads.h"
#include "util/main_guard.h"
#include "util/parallel_for.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

int main(int argc, char** argv) {
  using namespace hapstate;
  limit_math_threads();
  std::string out = "stress";
  std::string filter;
  int threads = 1;
  bool full = false, quick = false, no_retry = false;
  double wall_cap = 120;
  CLI::App app{
      "hapstate-stress: run the precise path solver over a matrix of material law x Poisson's "
      "ratio x load (stretch, compression, shear) x step size (one grid spacing, the whole path "
      "in one move) x mesh quality (regular, slivers) x probe (node, patch, contact) on a small "
      "bar, and write stress.csv (one row per case) and stress.md (success rates, strain "
      "reached, failures with reasons). A failed case is run again with moves of a quarter grid "
      "spacing (column retry_fine_step).\n"
      "Exit codes: 0 every case converged with finite outputs or failed with a recorded "
      "reason; 1 a bug (a NaN in a converged output, an exception, a failure without a reason) "
      "or an internal error; 2 bad options; 3 a case hit the wall-time cap; 4 cannot write."};
  use_hapstate_help(app);
  app.add_option("--out", out, "output folder (created)");
  auto* q = app.add_flag("--quick", quick, "the CI subset (the default)");
  app.add_flag("--full", full, "the full matrix (720 cases)")->excludes(q);
  app.add_option(
      "--filter", filter,
      "keep the cases whose id (law/nuV/load/step/mesh/probe, e.g. "
      "stvk/nu0.3/compress/whole/sliver/patch) contains every comma-separated term (default: "
      "every case)");
  app.add_option("--threads", threads, "cases solved in parallel")->check(CLI::Range(1, 256));
  app.add_option("--wall-cap", wall_cap, "seconds per case before it is stopped (between moves)")
      ->check(positive());
  app.add_flag("--no-retry", no_retry, "do not run failed cases again with smaller moves");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return exit_after_parse_error(app, e, "hapstate-stress");
  }
  return guarded_main("hapstate-stress", [&] {
    const std::vector<StressCase> cases = filter_cases(stress_matrix(full), filter);
    if (cases.empty()) throw InputError("--filter '" + filter + "' keeps no case");
    std::vector<StressOutcome> outcomes(cases.size());
    parallel_for(cases.size(), threads, [&](std::size_t i, int) {
      outcomes[i] = run_stress_case(cases[i], wall_cap, !no_retry);
      const StressOutcome& o = outcomes[i];
      std::fprintf(stderr, "%4zu/%zu %-44s %-9s %6.0f ms %s%s\n", i + 1, cases.size(),
                   o.c.id().c_str(), o.status.c_str(), o.wall_ms, o.failure.c_str(),
                   o.retry.empty() ? "" : (" retry " + o.retry).c_str());
    });
    std::filesystem::create_directories(out);
    const std::filesystem::path csv = std::filesystem::path(out) / "stress.csv";
    const std::filesystem::path md = std::filesystem::path(out) / "stress.md";
    write_stress_csv(outcomes, csv);
    const std::string report = stress_markdown(outcomes);
    std::ofstream(md) << report;
    std::printf("%s\ncsv: %s\nmarkdown: %s\n", report.c_str(), csv.c_str(), md.c_str());
    int code = kExitOk;
    for (const StressOutcome& o : outcomes) {
      if (o.bug()) {
        std::fprintf(stderr, "hapstate-stress: BUG: %s: %s: %s\n", o.c.id().c_str(),
                     o.status.c_str(), o.reason.c_str());
        code = kExitFailure;
      } else if (o.status == "wall_cap" && code == kExitOk) {
        code = kExitSolveFailed;
      }
    }
    return code;
  });
}
