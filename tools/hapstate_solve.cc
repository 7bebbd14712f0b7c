// hapstate-solve: the precise path solver. Solves the equilibrium of the scene's body at every
// point of a probe path, step by step from rest, and writes one CSV row per point.
#include "ccx/deck.h"
#include "io/probe_path.h"
#include "io/vtu_writer.h"
#include "scene/bind.h"
#include "scene/scene.h"
#include "solver/path_solver.h"
#include "statespace/math_threads.h"
#include "statespace/probe_model.h"
#include "util/main_guard.h"
#include "util/progress.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <map>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <optional>
#include <thread>

#include <sched.h>

namespace hapstate {
namespace {

constexpr int kThreadsFromDofs = 4000;

struct Options {
  std::string scene;
  std::string path_csv;
  std::vector<double> straight;
  std::vector<double> by;
  int steps = 10;
  int random_steps = 0;
  std::uint64_t seed = 1;
  double step_length = 0;
  std::string output;
  std::string displacements;
  std::string vtu_dir;
  std::string ccx_dir;
  bool quiet = false;
  bool timings = false;
  bool rest = false;
  SolverAlgorithm algorithm = SolverAlgorithm::kFast;
  int threads = 0;  // 0: automatic (threads_for)
};

// --threads' default: threads pay inside one solve from a few thousand DOFs on (see
// docs/benchmarks.md, "Threads inside one solve"); below, their start-up costs more than the
// work they share.
int threads_for(int dofs) {
  cpu_set_t allowed;  // the cores this process may run on (taskset, cgroups), not the machine's
  const int cores = sched_getaffinity(0, sizeof allowed, &allowed) == 0
                        ? std::max(1, CPU_COUNT(&allowed))
                        : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return dofs >= kThreadsFromDofs ? cores : 1;
}

ProbePath make_path(const Options& o, const Scene& scene, const Problem& problem) {
  if (!o.path_csv.empty()) return read_probe_path(o.path_csv);
  if (!o.by.empty()) {
    const Eigen::Vector3d d(o.by[0], o.by[1], o.by[2]);
    return straight_path(problem.probe_rest, problem.probe_rest + d, o.steps);
  }
  if (!o.straight.empty()) {
    return straight_path(problem.probe_rest,
                         Eigen::Vector3d(o.straight[0], o.straight[1], o.straight[2]), o.steps);
  }
  // Random walk inside the workspace (grid box, or 4 spacings around the probe).
  const double h = smallest_grid_spacing(scene.grid);
  Eigen::Vector3d lo = problem.probe_rest - Eigen::Vector3d::Constant(4 * h);
  Eigen::Vector3d hi = problem.probe_rest + Eigen::Vector3d::Constant(4 * h);
  if (scene.grid.box) {  // drawn around the mesh as drawn: it follows the grab point's sag
    lo = scene.grid.box->min + problem.probe_sag;
    hi = scene.grid.box->max + problem.probe_sag;
  }
  const double length = o.step_length > 0 ? o.step_length : h;
  return random_path(problem.probe_rest, o.random_steps, length, lo, hi, o.seed);
}

// --rest: the loaded rest state alone (solved by build_problem), as a node table, a VTU file
// and/or a CalculiX deck of its gravity step.
int run_rest(const Options& o) {
  SceneParseOptions parse;
  parse.require_probe = false;
  const Scene scene = load_scene(o.scene, parse);
  MeshReport report;
  const Problem problem = build_problem(scene, &report);
  for (const auto& w : report.warnings)
    std::fprintf(stderr, "hapstate-solve: mesh: %s\n", w.c_str());
  const Eigen::Matrix3Xd u =
      problem.rest_m.size() > 0
          ? Eigen::Matrix3Xd(Eigen::Map<const Eigen::Matrix3Xd>(problem.rest_m.data(), 3,
                                                                problem.mesh.num_nodes()) /
                             problem.unit)
          : Eigen::Matrix3Xd::Zero(3, problem.mesh.num_nodes());
  Eigen::Index worst = 0;
  const double sag = u.cols() > 0 ? u.colwise().norm().maxCoeff(&worst) : 0.0;
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();
  for (int n = 0; n < problem.mesh.num_nodes(); ++n)
    if (problem.loads.has_force()) weight += problem.loads.force.segment<3>(3 * n);
  if (!problem.loads.has_force()) {
    std::printf(
        "hapstate-solve: no body force (no [loads] gravity): the rest state is the mesh "
        "as drawn\n");
  } else {
    const Eigen::Vector3d x = problem.mesh.nodes.col(worst);
    std::printf(
        "hapstate-solve: loaded rest state: weight %.6g N (%.6g kg); the largest "
        "displacement %.6g mesh units, node %lld at (%.6g, %.6g, %.6g) as drawn, moved "
        "by (%.6g, %.6g, %.6g)\n",
        weight.norm(), weight.norm() / problem.loads.gravity.norm(), sag,
        static_cast<long long>(worst), x.x(), x.y(), x.z(), u(0, worst), u(1, worst), u(2, worst));
    if (!problem.constraints.probe_nodes.empty())
      std::printf(
          "hapstate-solve: the grab point moved by (%.6g, %.6g, %.6g) mesh units to "
          "(%.6g, %.6g, %.6g)\n",
          problem.probe_sag.x(), problem.probe_sag.y(), problem.probe_sag.z(),
          problem.probe_rest.x(), problem.probe_rest.y(), problem.probe_rest.z());
  }
  if (!o.output.empty()) {
    std::ofstream out(o.output);
    if (!out) throw InputError(o.output + ": cannot write output CSV");
    out << "node,x,y,z,ux,uy,uz\n" << std::setprecision(12);
    for (int n = 0; n < problem.mesh.num_nodes(); ++n) {
      const Eigen::Vector3d x = problem.mesh.nodes.col(n);
      out << n << ',' << x.x() << ',' << x.y() << ',' << x.z() << ',' << u(0, n) << ',' << u(1, n)
          << ',' << u(2, n) << '\n';
    }
    if (!out) throw InputError(o.output + ": write failed");
  }
  if (!o.vtu_dir.empty()) {
    std::filesystem::create_directories(o.vtu_dir);
    write_vtu(std::filesystem::path(o.vtu_dir) / "rest.vtu", problem.mesh, u);
  }
  if (!o.ccx_dir.empty()) {
    if (!problem.loads.has_force())
      throw InputError(o.scene +
                       ": --rest --export-ccx: no gravity ([loads]), so no rest step "
                       "to export (the rest state is the mesh as drawn)");
    write_ccx_deck(problem, {}, o.ccx_dir);
  }
  return kExitOk;
}

int run(const Options& o) {
  if (o.rest) return run_rest(o);
  const Scene scene = load_scene(o.scene);
  MeshReport report;
  const Problem problem = build_problem(scene, &report);
  for (const auto& w : report.warnings)
    std::fprintf(stderr, "hapstate-solve: mesh: %s\n", w.c_str());
  if (!o.quiet) std::fprintf(stderr, "hapstate-solve: %s\n", describe_grab(scene, problem).c_str());
  const ProbePath path = make_path(o, scene, problem);

  const bool contact = problem.contact.has_value();
  if (!o.ccx_dir.empty() && contact) {
    throw InputError(o.scene +
                     ": --export-ccx: a contact probe cannot be exported (the "
                     "CalculiX deck prescribes grabbed nodes; contact is not modelled there)");
  }
  if (!o.ccx_dir.empty()) {
    write_ccx_deck(problem, path, o.ccx_dir);
    if (!o.quiet)
      std::fprintf(stderr, "hapstate-solve: wrote CalculiX deck to %s\n", o.ccx_dir.c_str());
    if (o.output.empty()) return kExitOk;
  }

  std::ofstream out(o.output);
  if (!out) throw InputError(o.output + ": cannot write output CSV");
  out << "step,x,y,z,fx,fy,fz,residual,iterations,substeps,cutbacks,wall_ms,status"
      << (contact ? ",touched,active_set_changes\n" : "\n") << std::setprecision(12);
  std::ofstream disp;
  if (!o.displacements.empty()) {
    disp.open(o.displacements);
    if (!disp) throw InputError(o.displacements + ": cannot write displacement CSV");
    disp << "step,node,ux,uy,uz\n" << std::setprecision(12);
  }
  std::vector<std::pair<double, std::string>> frames;
  if (!o.vtu_dir.empty()) std::filesystem::create_directories(o.vtu_dir);

  PathSolver solver(problem);
  solver.set_algorithm(o.algorithm);
  // The probe as the state space sees it: a contact path may start anywhere clear of the body.
  const std::unique_ptr<ProbeModel> probe = make_probe_model(problem);
  if (!path.empty()) probe->start_path_at(solver, path.front());
  const int threads = o.threads > 0 ? o.threads : threads_for(solver.num_dofs());
  set_math_threads(threads);
  solver.set_threads(threads);
  Progress progress("hapstate-solve", static_cast<long long>(path.size()),
                    o.quiet ? nullptr : stderr);
  long long failures = 0;
  std::vector<double> wall_ms;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const int step = static_cast<int>(k) + 1;
    const MoveResult r = probe->move_to(solver, path[k]);
    wall_ms.push_back(r.wall_ms);
    if (!r.ok) {
      ++failures;
      std::fprintf(stderr, "hapstate-solve: step %d (%g, %g, %g) failed: %s: %s\n", step,
                   path[k].x(), path[k].y(), path[k].z(), failure_name(r.failure),
                   r.reason.c_str());
    }
    // On failure the solver stays at the last converged state; the row reports that state's force.
    const Eigen::Vector3d f = solver.force_felt();
    out << step << ',' << path[k].x() << ',' << path[k].y() << ',' << path[k].z() << ',' << f.x()
        << ',' << f.y() << ',' << f.z() << ',' << r.residual << ',' << r.iterations << ','
        << r.substeps << ',' << r.cutbacks << ',' << r.wall_ms << ','
        << (r.ok ? "ok" : failure_name(r.failure));
    if (contact) out << ',' << solver.touched_nodes().size() << ',' << r.active_set_iterations;
    out << '\n';
    if (disp.is_open() || !o.vtu_dir.empty()) {
      const Eigen::Matrix3Xd u = solver.displacements();
      if (disp.is_open())
        for (int n = 0; n < u.cols(); ++n)
          disp << step << ',' << n << ',' << u(0, n) << ',' << u(1, n) << ',' << u(2, n) << '\n';
      if (!o.vtu_dir.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "step_%05d.vtu", step);
        write_vtu(std::filesystem::path(o.vtu_dir) / name, problem.mesh, u);
        frames.emplace_back(step, name);
      }
    }
    progress.update(step, failures);
  }
  progress.finish();
  if (o.timings) {
    const SolverTimings& t = solver.timings();
    std::fprintf(stderr,
                 "hapstate-solve: timings: symbolic analysis %.3f ms; assembly %.3f ms x %lld; "
                 "factorisation %.3f ms x %lld (%lld PSD fallbacks); solve %.3f ms total (%lld "
                 "conjugate-gradient iterations)\n",
                 1e3 * t.analyze, 1e3 * t.assembly / std::max(1LL, t.assemblies), t.assemblies,
                 1e3 * t.factorize / std::max(1LL, t.factorisations), t.factorisations,
                 t.psd_fallbacks, 1e3 * t.solve, t.inner_iterations);
    const SparseCholesky& c = solver.linear_solver();
    std::fprintf(
        stderr,
        "hapstate-solve: %d DOFs, factor %s (%s ordering), nnz(L) %.3g, %.3g flop, %.1f MB; "
        "%lld back-substitutions\n",
        solver.num_dofs(), c.method(), c.ordering(), c.factor_nonzeros(), c.factor_flops(),
        c.factor_bytes() / 1e6, t.back_substitutions);
    if (const ContactTimings* ct = solver.contact_timings()) {
      const double total_ms = [&] {
        double ms = 0;
        for (double w : wall_ms) ms += w;
        return ms;
      }();
      std::fprintf(stderr,
                   "hapstate-solve: collision detection %.4f ms x %lld (%zu candidate surface "
                   "nodes), %.3f %% of the path's solve time\n",
                   1e3 * ct->detection / std::max(1LL, ct->queries), ct->queries,
                   problem.contact->candidates.size(),
                   total_ms > 0 ? 100 * 1e3 * ct->detection / total_ms : 0.0);
    }
  }
  if (!o.vtu_dir.empty()) write_pvd(std::filesystem::path(o.vtu_dir) / "path.pvd", frames);
  if (!out) throw InputError(o.output + ": write failed");
  return failures > 0 ? kExitSolveFailed : kExitOk;
}

}  // namespace
}  // namespace hapstate

int main(int argc, char** argv) {
  using namespace hapstate;
  Options o;
  CLI::App app{
      "hapstate-solve: precise non-linear FEM solve of a probe path (the reference the "
      "playback is measured against).\nExit codes: 0 ok, 1 internal error, 2 bad input, "
      "3 some path point failed to converge (reported, run completed)."};
  use_hapstate_help(app);
  app.add_option("scene", o.scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  auto* path_opt =
      app.add_option("--path", o.path_csv,
                     "probe path CSV with header x,y,z: absolute probe positions "
                     "(scene units), solved in order starting from rest (the path: one of --path, "
                     "--straight, --by, --random; default: none)")
          ->check(CLI::ExistingFile);
  auto* straight_opt =
      app.add_option("--straight", o.straight,
                     "straight path from the rest position to X Y Z (default: none)")
          ->expected(3);
  auto* by_opt =
      app.add_option(
             "--by", o.by,
             "straight path from the rest position by DX DY DZ (scene units; default: none)")
          ->expected(3);
  app.add_option("--steps", o.steps, "points on a --straight or --by path")
      ->check(CLI::Range(1, 100000000));
  auto* random_opt = app.add_option("--random", o.random_steps,
                                    "seeded random walk of N points from the rest position, "
                                    "inside the grid workspace (default: none)")
                         ->check(CLI::Range(1, 100000000));
  app.add_option("--seed", o.seed, "seed of --random");
  app.add_option("--step-length", o.step_length,
                 "step of --random in scene units (default: the grid spacing)")
      ->check(positive());
  path_opt->excludes(straight_opt)->excludes(random_opt)->excludes(by_opt);
  straight_opt->excludes(random_opt)->excludes(by_opt);
  random_opt->excludes(by_opt);
  app.add_option("-o,--output", o.output,
                 "output CSV: step,x,y,z,fx,fy,fz,residual,iterations,substeps,cutbacks,wall_ms,"
                 "status (f = force felt by the user, N); a contact probe adds touched (nodes "
                 "the sphere holds) and active_set_changes (default: none; needed unless "
                 "--export-ccx)");
  app.add_option("--displacements", o.displacements,
                 "also write every node's displacement per step: CSV step,node,ux,uy,uz "
                 "(default: not written)");
  app.add_option("--vtu", o.vtu_dir,
                 "also write the mesh per step as VTU + path.pvd: the mesh as drawn with "
                 "its 'displacement' (ParaView: Warp By Vector, scale 1) (default: not written)");
  app.add_option("--export-ccx", o.ccx_dir,
                 "write the same problem as a CalculiX deck (DIR/problem.inp, see "
                 "tools/ccx_compare.py; default: not written)");
  app.add_flag("--rest", o.rest,
               "solve the loaded rest state alone (gravity and supports, the probe holding "
               "nothing; the scene may omit [probe] and [grid]): prints the weight and the "
               "largest sag; -o writes node,x,y,z,ux,uy,uz (mesh units), --vtu DIR/rest.vtu, "
               "--export-ccx a deck of its gravity step");
  app.add_flag("-q,--quiet", o.quiet, "no progress line");
  app.add_option("--algorithm", o.algorithm,
                 "fast (default): one sub-step per move where it converges, inexact Newton "
                 "preconditioned by a kept factorisation; "
                 "reference: the paper's fixed sub-steps with full Newton (for comparisons)")
      ->option_text(choices({"fast", "reference"}))
      ->transform(CLI::CheckedTransformer(std::map<std::string, SolverAlgorithm>{
          {"fast", SolverAlgorithm::kFast}, {"reference", SolverAlgorithm::kReference}}));
  app.add_option(
         "--threads", o.threads,
         "threads inside the solve: element assembly (OpenMP) and the BLAS of the "
         "factorisation (OpenBLAS; the environment's OMP_NUM_THREADS and "
         "OPENBLAS_NUM_THREADS are overridden; results do not depend on it beyond round-off "
         "in the factorisation) (default: all cores from " +
             std::to_string(kThreadsFromDofs) + " DOFs on, else 1)")
      ->check(positive());
  app.add_flag(
      "--timings", o.timings,
      "print time per assembly / factorisation / solve and the symbolic analysis (and, for a "
      "contact probe, collision detection)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;  // --help is not an error
  }
  return guarded_main("hapstate-solve", [&] {
    if (o.rest) {
      if (!o.path_csv.empty() || !o.straight.empty() || !o.by.empty() || o.random_steps > 0)
        throw InputError("--rest takes no probe path");
      return run(o);
    }
    if (o.path_csv.empty() && o.straight.empty() && o.by.empty() && o.random_steps == 0)
      throw InputError(
          "give a probe path: --path FILE, --straight X Y Z, --by DX DY DZ or --random N");
    if (o.output.empty() && o.ccx_dir.empty())
      throw InputError("give -o OUT.csv (or --export-ccx DIR)");
    return run(o);
  });
}
