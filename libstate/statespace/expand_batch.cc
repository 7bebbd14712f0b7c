#include "statespace/expand_batch.h"

#include "util/error.h"
#include "util/grid_direction.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>

namespace hapstate {

SourceLoader blob_source_loader(const BlobStore& blobs, std::vector<double> rest_u,
                                const VectorLayout& layout) {
  return [&blobs, rest_u = std::move(rest_u), layout](const Configuration& c) {
    return load_config_vectors(blobs, c, rest_u, layout);
  };
}

// The pool's shared state, under `mutex`. Transition work is a list of tasks (the wave's copy,
// or solve()'s), handed out from `next` up to `horizon`; results wait in `results` until
// collected. Stiffness work is a list handed out from `stiffness_next`.
struct TransitionSolver::Pool {
  std::mutex mutex;
  std::condition_variable work;  // the threads wait here for work or stop
  std::condition_variable done;  // the caller waits here for results
  std::vector<std::thread> threads;
  bool stop = false;
  std::exception_ptr error;
  int busy = 0;  // threads working on something they claimed

  std::vector<TransitionTask> tasks;
  std::uint64_t list = 0;  // which list `tasks` holds (a thread's reserved run is of one)
  std::size_t next = 0, horizon = 0, window = 0;
  std::map<std::size_t, TransitionSolve> results;

  const std::vector<StiffnessTask>* stiffness_tasks = nullptr;
  std::size_t stiffness_next = 0, stiffness_left = 0;
  std::vector<StiffnessResult>* stiffness_results = nullptr;
};

TransitionSolver::TransitionSolver(const Problem& problem, const ProbeModel& probe,
                                   SourceLoader sources, int threads, SolverAlgorithm algorithm)
    : problem_(problem),
      probe_(probe),
      sources_loader_(std::move(sources)),
      threads_(std::max(1, threads)),
      algorithm_(algorithm),
      pool_(std::make_unique<Pool>()) {
  solvers_.resize(threads_);
  sources_.resize(threads_);
  pool_->window = lookahead(threads_, 3 * static_cast<int>(problem.mesh.num_nodes()));
}

TransitionSolver::~TransitionSolver() { finish(); }

std::size_t TransitionSolver::lookahead(int threads, int num_dofs) {
  // A whole source is 26 directions; four of them per thread keep every thread busy while the
  // slowest direction of a batch finishes and the batch is stored.
  const std::size_t wanted = 4 * grid::kDirections * static_cast<std::size_t>(std::max(1, threads));
  // A result holds u (float64) and, for a midpoint, its u and three slopes (float32).
  const std::size_t bytes_per_result = 24 * static_cast<std::size_t>(std::max(1, num_dofs));
  const std::size_t affordable = (std::size_t{1} << 30) / bytes_per_result;
  return std::max<std::size_t>(2 * std::max(1, threads), std::min(wanted, affordable));
}

void TransitionSolver::start_threads() {
  if (!pool_->threads.empty()) return;
  pool_->threads.reserve(static_cast<std::size_t>(threads_));
  for (int w = 0; w < threads_; ++w) pool_->threads.emplace_back([this, w] { worker_loop(w); });
}

void TransitionSolver::finish() {
  {
    std::lock_guard<std::mutex> lock(pool_->mutex);
    pool_->stop = true;
  }
  pool_->work.notify_all();
  for (std::thread& t : pool_->threads) t.join();
  pool_->threads.clear();
}

void TransitionSolver::worker_loop(int worker) {
  Pool& p = *pool_;
  try {
    if (!solvers_[worker]) {
      solvers_[worker] = std::make_unique<PathSolver>(problem_);
      solvers_[worker]->set_algorithm(algorithm_);
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(p.mutex);
    if (!p.error) p.error = std::current_exception();
    p.next = p.horizon;
    p.done.notify_all();
    return;
  }
  struct Run {
    std::uint64_t list = 0;
    std::size_t begin = 0, end = 0;
  } run;  // tasks reserved by this thread: [begin, end) of list `list`
  std::unique_lock<std::mutex> lock(p.mutex);
  for (;;) {
    p.work.wait(lock, [&] {
      return p.stop ||
             (!p.error && ((p.stiffness_tasks && p.stiffness_next < p.stiffness_tasks->size()) ||
                           (run.begin < run.end && run.list == p.list) || p.next < p.horizon));
    });
    if (p.stop) return;
    ++p.busy;
    try {
      if (p.stiffness_tasks && p.stiffness_next < p.stiffness_tasks->size()) {
        const std::size_t k = p.stiffness_next++;
        const StiffnessTask& task = (*p.stiffness_tasks)[k];
        std::vector<StiffnessResult>* results = p.stiffness_results;
        lock.unlock();
        StiffnessResult r = stiffness_one(worker, task);
        lock.lock();
        (*results)[k] = std::move(r);
        --p.stiffness_left;
      } else {
        // The next task of this thread's run (consecutive tasks of one source, reserved when
        // the last run ended), so that a waiting stiffness is taken between two of them.
        if (run.begin >= run.end || p.list != run.list) {
          run.list = p.list;
          run.begin = p.next;
          run.end = run.begin + 1;
          const std::size_t most =
              guided_run(p.horizon - p.next, static_cast<std::size_t>(threads_), 1);
          while (run.end < p.horizon && run.end - run.begin < most &&
                 p.tasks[run.end].source.id == p.tasks[run.begin].source.id)
            ++run.end;
          p.next = run.end;
        }
        const std::size_t k = run.begin++;
        const TransitionTask& task = p.tasks[k];  // not replaced while busy > 0
        lock.unlock();
        TransitionSolve r = solve_one(worker, task);
        lock.lock();
        p.results.emplace(k, std::move(r));
      }
    } catch (...) {
      if (!lock.owns_lock()) lock.lock();
      if (!p.error) p.error = std::current_exception();
      p.next = p.horizon;  // nothing more is handed out
    }
    --p.busy;
    p.done.notify_all();
  }
}

template <typename Done>
void TransitionSolver::wait_for(std::unique_lock<std::mutex>& lock, Done&& done) {
  pool_->done.wait(lock, [&] { return pool_->error || done(); });
  if (pool_->error) std::rethrow_exception(pool_->error);
}

void TransitionSolver::start_wave(const std::vector<TransitionTask>& tasks) {
  std::unique_lock<std::mutex> lock(pool_->mutex);
  pool_->horizon = pool_->next;  // hand out nothing more of the last list
  wait_for(lock, [&] { return pool_->busy == 0; });
  pool_->tasks = tasks;
  ++pool_->list;
  pool_->next = pool_->horizon = 0;
  pool_->results.clear();
}

std::vector<TransitionSolve> TransitionSolver::solve_range(std::size_t begin, std::size_t end,
                                                           std::size_t ahead_end) {
  Pool& p = *pool_;
  std::unique_lock<std::mutex> lock(p.mutex);
  if (end > p.tasks.size() || begin > end)
    throw std::logic_error("TransitionSolver::solve_range past the wave");
  p.horizon = std::max({p.horizon, end, std::min({p.tasks.size(), end + p.window, ahead_end})});
  start_threads();
  p.work.notify_all();
  wait_for(lock, [&] {
    for (std::size_t k = begin; k < end; ++k)
      if (!p.results.count(k)) return false;
    return true;
  });
  std::vector<TransitionSolve> out;
  out.reserve(end - begin);
  for (std::size_t k = begin; k < end; ++k) {
    auto it = p.results.find(k);
    out.push_back(std::move(it->second));
    p.results.erase(it);
  }
  return out;
}

std::vector<TransitionSolve> TransitionSolver::solve(std::span<const TransitionTask> tasks) {
  start_wave(std::vector<TransitionTask>(tasks.begin(), tasks.end()));
  return solve_range(0, tasks.size(), tasks.size());
}

std::vector<StiffnessResult> TransitionSolver::stiffnesses(
    const std::vector<StiffnessTask>& tasks) {
  std::vector<StiffnessResult> results(tasks.size());
  if (tasks.empty()) return results;
  Pool& p = *pool_;
  std::unique_lock<std::mutex> lock(p.mutex);
  p.stiffness_tasks = &tasks;
  p.stiffness_next = 0;
  p.stiffness_left = tasks.size();
  p.stiffness_results = &results;
  start_threads();
  p.work.notify_all();
  try {
    wait_for(lock, [&] { return p.stiffness_left == 0; });
  } catch (...) {
    // No thread may still write into `results` once it is gone.
    p.stiffness_tasks = nullptr;
    p.done.wait(lock, [&] { return p.busy == 0; });
    throw;
  }
  p.stiffness_tasks = nullptr;
  p.stiffness_results = nullptr;
  return results;
}

const ConfigVectors& TransitionSolver::source_vectors(int worker, const Configuration& source) {
  std::optional<LoadedSource>& loaded = sources_[worker];
  if (!loaded || loaded->config.id != source.id || loaded->config.blob != source.blob) {
    loaded.reset();
    loaded = LoadedSource{source, sources_loader_(source)};
  }
  return loaded->vectors;
}

std::size_t guided_run(std::size_t left, std::size_t consumers, std::size_t least) {
  least = std::max<std::size_t>(1, least);
  return std::clamp<std::size_t>(left / (2 * std::max<std::size_t>(1, consumers)), least,
                                 Direction::kCount * least);
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
    // between check-points. The second half starts from it (the stiffness's factorisation is
    // the one its predictor would make, kept for it); a half that
    // fails is not recorded, and the move is then solved whole from the source as any other.
    MoveResult half = probe_.move_to(solver, 0.5 * (task.from + task.to));
    if (half.ok) {
      const Eigen::Vector3d f = solver.force_felt();
      out.midpoint_force = std::array<double, 3>{f.x(), f.y(), f.z()};
      const Eigen::VectorXd& u_m = solver.state_m();
      out.midpoint_u.resize(static_cast<std::size_t>(u_m.size()));
      for (Eigen::Index d = 0; d < u_m.size(); ++d)
        out.midpoint_u[d] = static_cast<float>(u_m[d] / problem_.unit);
      const long long before = solver.timings().factorisations;
      Eigen::MatrixX3d du_dp;
      const Eigen::Matrix3d k = solver.haptic_stiffness(&du_dp, /*keep_factor=*/true);
      half.factorisations += static_cast<int>(solver.timings().factorisations - before);
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

RestStiffness rest_stiffness(const Problem& problem) {
  PathSolver solver(problem);
  Eigen::MatrixX3d du_dp;
  const Eigen::Matrix3d k = solver.haptic_stiffness(&du_dp);
  StiffnessResult r = stiffness_result(k, du_dp);
  return RestStiffness{r.stiffness, std::move(r.du_dp)};
}

RestStiffness zero_stiffness(const StateDir& dir, const Problem& problem) {
  if (auto stored = stored_rest_stiffness(dir, problem.mesh.num_nodes())) return *stored;
  return rest_stiffness(problem);
}

StiffnessResult TransitionSolver::stiffness_one(int worker, const StiffnessTask& task) {
  PathSolver& solver = *solvers_[worker];
  probe_.set_state(solver, *task.vectors, task.position);
  const long long before = solver.timings().factorisations;
  Eigen::MatrixX3d du_dp;
  const Eigen::Matrix3d stiffness = solver.haptic_stiffness(&du_dp);
  StiffnessResult result = stiffness_result(stiffness, du_dp);
  result.factorisations = static_cast<int>(solver.timings().factorisations - before);
  return result;
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
