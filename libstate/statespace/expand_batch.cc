#include "statespace/expand_batch.h"

#include "util/error.h"

#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>

namespace hapstate {

SourceLoader blob_source_loader(const BlobStore& blobs, int num_dofs, const VectorLayout& layout) {
  return [&blobs, num_dofs, layout](const Configuration& c) {
    return load_config_vectors(blobs, c, num_dofs, layout);
  };
}

TransitionSolver::TransitionSolver(const Problem& problem, const ProbeModel& probe,
                                   SourceLoader sources, int threads, SolverAlgorithm algorithm)
    : problem_(problem),
      probe_(probe),
      sources_loader_(std::move(sources)),
      threads_(std::max(1, threads)),
      algorithm_(algorithm) {
  solvers_.resize(threads_);
  sources_.resize(threads_);
}

TransitionSolver::~TransitionSolver() = default;

const ConfigVectors& TransitionSolver::source_vectors(int worker, const Configuration& source) {
  std::optional<LoadedSource>& loaded = sources_[worker];
  if (!loaded || loaded->config.id != source.id || loaded->config.blob != source.blob) {
    loaded.reset();
    loaded = LoadedSource{source, sources_loader_(source)};
  }
  return loaded->vectors;
}

bool records_midpoint(Direction direction) {
  const auto o = direction.offset();
  return o[0] >= 0 && o[1] >= 0 && o[2] >= 0;
}

namespace {

// A move solved after a first half costs both: sub-steps, iterations, factorisations and time
// add up. Of the start state's factorisations (shared by a source's directions) only those of
// moves that started at the source count: `second_from_source` false, the second half started
// half-way, and what it factorised there is the transition's own.
void add_cost(const MoveResult& first, bool second_from_source, MoveResult* second) {
  second->substeps += first.substeps;
  second->cutbacks += first.cutbacks;
  second->iterations += first.iterations;
  second->factorisations += first.factorisations;
  second->start_factorisations =
      first.start_factorisations + (second_from_source ? second->start_factorisations : 0);
  second->active_set_iterations += first.active_set_iterations;
  second->wall_ms += first.wall_ms;
}

}  // namespace

TransitionSolve TransitionSolver::solve_one(int worker, const TransitionTask& task) {
  PathSolver& solver = *solvers_[worker];
  TransitionSolve out;
  if (!task.target) return out;
  out.solved = true;
  if (!task.source.blob && probe_.trivial_move(task.from, task.to)) {
    // The zero configuration moved past the body: still at rest, nothing touched.
    out.trivial = true;
    if (records_midpoint(task.direction)) {
      out.midpoint_force = std::array<double, 3>{};
      out.midpoint_stiffness = std::array<double, 9>{};
      out.midpoint_u.assign(solver.num_dofs(), 0.0f);
      out.midpoint_du_dp.assign(3 * static_cast<std::size_t>(solver.num_dofs()), 0.0f);
    }
    out.vectors.u.assign(solver.num_dofs(), 0.0);
    out.vectors.t.assign(probe_.layout().t_size(0), 0.0);  // the layout of a stored zero state
    out.vectors.h.assign(probe_.layout().h_size(0), 0.0);
    return out;
  }
  probe_.set_state(solver, source_vectors(worker, task.source), task.from);
  if (records_midpoint(task.direction)) {
    // Half-way first: the force and the haptic stiffness there are the interpolant's values
    // between check-points. The second half starts from it (the stiffness's factorisation does
    // not change it: each sub-step's predictor assembles and factorises anew); a half that
    // fails is not recorded, and the move is then solved whole from the source as any other.
    MoveResult half = probe_.move_to(solver, 0.5 * (task.from + task.to));
    if (half.ok) {
      const Eigen::Vector3d f = solver.force_felt();
      out.midpoint_force = std::array<double, 3>{f.x(), f.y(), f.z()};
      const Eigen::VectorXd& u_m = solver.state_m();
      out.midpoint_u.resize(static_cast<std::size_t>(u_m.size()));
      for (Eigen::Index d = 0; d < u_m.size(); ++d)
        out.midpoint_u[d] = static_cast<float>(u_m[d] / problem_.unit);
      const long long before = solver.timings().factorizations;
      Eigen::MatrixX3d du_dp;
      const Eigen::Matrix3d k = solver.haptic_stiffness(&du_dp);
      half.factorisations += static_cast<int>(solver.timings().factorizations - before);
      if (k.allFinite()) {
        std::array<double, 9> row_major{};
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) row_major[3 * r + c] = k(r, c);
        out.midpoint_stiffness = row_major;
      }
      if (k.allFinite()) {
        out.midpoint_du_dp = stiffness_result(k, du_dp).du_dp;
      } else {
        out.midpoint_u.clear();  // no slopes there: the corners' cubic serves
      }
      out.move = probe_.move_to(solver, task.to);
      add_cost(half, false, &out.move);
    } else {
      probe_.set_state(solver, source_vectors(worker, task.source), task.from);
      out.move = probe_.move_to(solver, task.to);
      add_cost(half, true, &out.move);
    }
    if (!out.move.ok) {
      out.midpoint_force.reset(), out.midpoint_stiffness.reset();
      out.midpoint_u.clear(), out.midpoint_du_dp.clear();
    }
  } else {
    out.move = probe_.move_to(solver, task.to);
  }
  if (!out.move.ok) return out;
  if (probe_.stores_touched()) out.vectors.touched = solver.touched_nodes();
  if (probe_.layout().multipliers) out.vectors.multipliers = solver.contact_multipliers();
  const Eigen::VectorXd& u_m = solver.state_m();
  out.vectors.u.resize(u_m.size());
  for (Eigen::Index k = 0; k < u_m.size(); ++k) out.vectors.u[k] = u_m[k] / problem_.unit;
  out.vectors.t = probe_.load_of(solver, task.to).values;
  const Eigen::VectorXd h = solver.probe_reactions();
  out.vectors.h.assign(h.data(), h.data() + h.size());
  const Eigen::Vector3d f = solver.force_felt();
  out.force = {f.x(), f.y(), f.z()};
  return out;
}

template <typename Body>
void TransitionSolver::for_each_parallel(std::size_t count, Body&& body) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&](int worker) {
    try {
      if (!solvers_[worker]) {
        solvers_[worker] = std::make_unique<PathSolver>(problem_);
        solvers_[worker]->set_algorithm(algorithm_);
      }
      for (std::size_t k = next++; k < count; k = next++) body(worker, k);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = count;
    }
  };
  const int workers =
      static_cast<int>(std::min<std::size_t>(threads_, std::max<std::size_t>(1, count)));
  if (workers <= 1) {
    work(0);
  } else {
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(workers));
    for (int w = 0; w < workers; ++w) pool.emplace_back(work, w);
    for (auto& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);
}

std::vector<TransitionSolve> TransitionSolver::solve(std::span<const TransitionTask> tasks) {
  std::vector<TransitionSolve> results(tasks.size());
  for_each_parallel(tasks.size(),
                    [&](int worker, std::size_t k) { results[k] = solve_one(worker, tasks[k]); });
  return results;
}

std::vector<TransitionSolve> TransitionSolver::solve_range(std::size_t begin, std::size_t end) {
  return solve(std::span<const TransitionTask>(*wave_).subspan(begin, end - begin));
}

StiffnessResult stiffness_result(const Eigen::Matrix3d& stiffness, const Eigen::MatrixX3d& du_dp) {
  StiffnessResult out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out.stiffness[3 * r + c] = std::isfinite(stiffness(r, c)) ? stiffness(r, c) : 0.0;
  out.du_dp.resize(static_cast<std::size_t>(du_dp.size()));
  Eigen::Map<Eigen::MatrixX3f>(out.du_dp.data(), du_dp.rows(), 3) =
      du_dp.unaryExpr([](double v) { return std::isfinite(v) ? static_cast<float>(v) : 0.0f; });
  return out;
}

StiffnessResult rest_stiffness(const Problem& problem) {
  PathSolver solver(problem);
  Eigen::MatrixX3d du_dp;
  const Eigen::Matrix3d k = solver.haptic_stiffness(&du_dp);
  return stiffness_result(k, du_dp);
}

std::vector<StiffnessResult> TransitionSolver::stiffnesses(
    const std::vector<StiffnessTask>& tasks) {
  std::vector<StiffnessResult> results(tasks.size());
  for_each_parallel(tasks.size(), [&](int worker, std::size_t k) {
    PathSolver& solver = *solvers_[worker];
    probe_.set_state(solver, *tasks[k].vectors, tasks[k].position);
    const long long before = solver.timings().factorizations;
    Eigen::MatrixX3d du_dp;
    const Eigen::Matrix3d stiffness = solver.haptic_stiffness(&du_dp);
    results[k] = stiffness_result(stiffness, du_dp);
    results[k].factorisations = static_cast<int>(solver.timings().factorizations - before);
  });
  return results;
}

SolverTimings TransitionSolver::timings() const {
  SolverTimings sum;
  for (const auto& solver : solvers_) {
    if (!solver) continue;
    sum += solver->timings();  // its contact fields are 0: taken from contact_timings()
    if (const ContactTimings* c = solver->contact_timings()) {
      sum.contact_detection += c->detection;
      sum.contact_queries += c->queries;
    }
  }
  return sum;
}

}  // namespace hapstate
