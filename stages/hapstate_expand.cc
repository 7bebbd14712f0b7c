// hapstate-expand: breadth-first expansion of the state space (the long stage).
#include "distributed/mpi_engine.h"
#include "stages/expand_stage.h"
#include "statespace/math_threads.h"
#include "util/cores.h"
#include "util/main_guard.h"
#include "util/stop_request.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <map>
#include <string>

namespace {

// --timings: where the expansion's time went (`solver_threads` solvers in all).
void print_timings(const hapstate::ExpandReport& r, int solver_threads, bool distributed) {
  using namespace hapstate;
  const SolverTimings& t = r.solver;
  const double cpu = t.assembly + t.factorize + t.solve;
  std::printf(
      "hapstate-expand: timings: wall %.2f s = solves %.2f s (%.0f%%) + storing %.2f s "
      "(%.0f%%) + other %.2f s; in the solvers (summed over %d threads%s): assembly "
      "%.0f%%, factorisation %.0f%%, solve %.0f%% of %.2f s; %.1f transitions/s, "
      "%.1f ms per solved transition; per solved transition %.2f factorisations (%.2f "
      "the transition's own, as the catalogue records them, the rest the source "
      "states', shared by their directions) and %.1f conjugate-gradient iterations\n",
      r.wall_s, r.solve_wall_s, 100 * r.solve_wall_s / r.wall_s, r.store_wall_s,
      100 * r.store_wall_s / r.wall_s, r.wall_s - r.solve_wall_s - r.store_wall_s, solver_threads,
      distributed ? ": the worker ranks' threads" : "", cpu > 0 ? 100 * t.assembly / cpu : 0,
      cpu > 0 ? 100 * t.factorize / cpu : 0, cpu > 0 ? 100 * t.solve / cpu : 0, cpu,
      r.decided / r.wall_s, r.solved ? 1e3 * r.wall_s / r.solved : 0.0,
      r.solved ? double(t.factorisations) / r.solved : 0.0,
      r.solved ? double(r.factorisations) / r.solved : 0.0,
      r.solved ? double(t.inner_iterations) / r.solved : 0.0);
  if (r.solved && t.factor_bytes > 0) {
    // Each back-substitution reads the factor twice (forward, then backward): the
    // conjugate-gradient iterations the factor rounded to float, the other solves the
    // double one; a factorisation writes it once. The tangent and the vectors the memory
    // bus also carries are smaller on these meshes.
    const double per = double(t.back_substitutions) / r.solved;
    const double single = double(t.single_back_substitutions) / r.solved;
    const double factorisations = double(t.factorisations) / r.solved;
    const double bytes = 2 * (per - single) * t.factor_bytes + 2 * single * t.single_factor_bytes +
                         factorisations * t.factor_bytes;
    std::printf(
        "hapstate-expand: timings: factor %.1f MB per solver (%.1f MB rounded to float); "
        "per solved transition %.1f back-substitutions (%.1f of them in float: the "
        "conjugate-gradient iterations) and %.2f factorisations: about %.0f MB of factor "
        "read or written; %.2f GB/s over the solves' wall time\n",
        t.factor_bytes / 1e6, t.single_factor_bytes / 1e6, per, single, factorisations, bytes / 1e6,
        r.solve_wall_s > 0 ? bytes * r.solved / r.solve_wall_s / 1e9 : 0.0);
  }
  if (t.contact_queries > 0) {
    std::printf(
        "hapstate-expand: timings: contact: %lld of the solved transitions were moves "
        "between free check-points (no solve); collision detection %.4f ms per "
        "probe position (%lld), %.3f%% of the solvers' time\n",
        r.trivial, 1e3 * t.contact_detection / static_cast<double>(t.contact_queries),
        t.contact_queries, cpu > 0 ? 100 * t.contact_detection / cpu : 0.0);
  }
}

// What it detected and chose (docs/distributed.md, "Layout").
void print_layout(const hapstate::MpiSession& mpi, int threads) {
  using namespace hapstate;
  std::string line = "hapstate-expand: " + std::to_string(usable_cores()) + " usable cores here";
  if (const int ranks = ranks_on_this_host(); ranks > 1)
    line += ", " + std::to_string(ranks) + " ranks of this job on this host";
  line += "; ";
  if (mpi.distributed()) line += std::to_string(mpi.size() - 1) + " worker ranks x ";
  line += std::to_string(threads) + (threads == 1 ? " solver thread" : " solver threads");
  if (mpi.distributed()) line += " each";
  std::fprintf(stderr, "%s\n", line.c_str());
}

// The run's report: what a resumed run cleaned up, and its one line.
void print_report(const hapstate::ExpandReport& r) {
  if (r.garbage_segments)
    std::fprintf(stderr,
                 "hapstate-expand: removed %zu unreferenced segment(s) left by an "
                 "interrupted run\n",
                 r.garbage_segments);
  if (r.interrupted_runs && !r.unchanged())
    std::fprintf(stderr, "hapstate-expand: resuming after %d interrupted run(s)\n",
                 r.interrupted_runs);
  std::printf("hapstate-expand: %s\n", r.message.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hapstate;
  // One BLAS/OpenMP thread per worker: set before any BLAS call (docs/state-space.md).
  limit_math_threads();
  // Under mpirun: rank 0 runs the stage, the other ranks solve for it (docs/distributed.md).
  MpiSession mpi(&argc, &argv);
  ExpandOptions o;
  std::string state;
  long long max_transitions = 0;
  double max_seconds = 0;
  bool quiet = false;
  CLI::App app{
      "hapstate-expand: compute transitions between neighbouring check-points in breadth-first "
      "waves from the zero configuration until every configuration with |force| <= "
      "probe.max_force has its 26 directions decided. Interrupt it at any time (even kill -9) "
      "and run it again to resume; the result does not depend on --threads, on the number of MPI "
      "ranks (mpirun -n N hapstate-expand ...: rank 0 coordinates, the others solve, each with "
      "--threads) or on interruptions.\n"
      "Exit codes: 0 complete, partial (a --max-* limit was reached) or nothing to do; 1 "
      "internal error; 130 stopped by Ctrl-C or SIGTERM (resumable; under mpirun every rank "
      "ends at once, also resumable); 2 bad options or state directory (not imported, grid out of "
      "date, "
      "missing or damaged segment, newer catalogue): nothing changed. Failed solves do not "
      "change the exit code: they are recorded as transitions with outcome 'failed'."};
  use_hapstate_help(app);
  app.add_option("--state", state, "state directory (after hapstate-grid)")->required();
  o.threads = default_threads();
  app.add_option("--threads", o.threads,
                 "worker threads, one FEM solver each (default: the cores this process may use, "
                 "shared among the MPI ranks on this host; here " +
                     std::to_string(o.threads) + ")")
      ->check(CLI::Range(1, 1024));
  app.add_option("--batch", o.batch_size,
                 "transitions per batch (one blob segment and one catalogue transaction each); "
                 "part of the result's layout: keep it fixed to compare runs")
      ->check(CLI::Range(1, 1000000));
  auto* mt = app.add_option("--max-transitions", max_transitions,
                            "stop at the first batch boundary after N transitions (exit 0, "
                            "outcome partial; default: no limit)")
                 ->check(CLI::Range(1LL, 1LL << 60));
  auto* ms = app.add_option("--max-seconds", max_seconds,
                            "stop at the first batch boundary after S seconds (exit 0, outcome "
                            "partial; default: no limit)")
                 ->check(positive());
  app.add_option("--algorithm", o.algorithm,
                 "fast (default): one sub-step per move where it converges, inexact Newton "
                 "preconditioned by a kept factorisation; "
                 "reference: the paper's fixed sub-steps with full Newton (for comparisons). The "
                 "same tolerance, so the same state space within it")
      ->option_text(choices({"fast", "reference"}))
      ->transform(CLI::CheckedTransformer(std::map<std::string, SolverAlgorithm>{
          {"fast", SolverAlgorithm::kFast}, {"reference", SolverAlgorithm::kReference}}));
  app.add_flag("-q,--quiet", quiet, "no progress line");
  bool timings = false;
  app.add_flag("--timings", timings,
               "print where the time went: parallel solves (assembly, factorisation, solve) "
               "and storing (level comparison, segments, catalogue)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parsed the same arguments and ends the same way.
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  if (mpi.distributed() && mpi.rank() > 0)
    return guarded_main("hapstate-expand (MPI worker)", [] {
      run_mpi_worker();
      return kExitOk;
    });
  const int code = guarded_main("hapstate-expand", [&] {
    o.state = state;
    if (mt->count()) o.max_transitions = max_transitions;
    if (ms->count()) o.max_seconds = max_seconds;
    o.progress = quiet ? nullptr : stderr;
    if (!quiet) print_layout(mpi, o.threads);
    install_stop_request_handler(
        "\nhapstate-expand: stopping after the current batch (Ctrl-C again stops at once; "
        "either way, run the same command again to resume)\n");
    if (mpi.distributed()) o.engine = mpi_engine_factory(mpi, o.threads, o.algorithm);
    const ExpandReport r = run_expand(o);
    print_report(r);
    if (timings && !r.unchanged() && r.wall_s > 0)
      print_timings(r, mpi.distributed() ? (mpi.size() - 1) * o.threads : o.threads,
                    mpi.distributed());
    if (!r.engine_summary.empty() && (timings || !quiet))
      std::printf("hapstate-expand: MPI: %s\n", r.engine_summary.c_str());
    if (r.stopped_by_signal) {
      std::fprintf(stderr, "hapstate-expand: stopped; run the same command again to resume\n");
      return kExitInterrupted;
    }
    return kExitOk;
  });
  release_mpi_workers(mpi);
  return code;
}
