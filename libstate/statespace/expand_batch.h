// The parallel part of the expand stage: solving a batch of transitions on N worker threads,
// one PathSolver per worker (kept across batches). Each solve is a pure function of the
// source configuration's stored vectors and the direction, so the results do not depend on
// the thread count or on which worker ran them. TransitionEngine is what the stage asks for
// solves: these threads, or worker ranks over MPI (distributed/).
#pragma once

#include "blobs/blob_store.h"
#include "catalogue/records.h"
#include "solver/path_solver.h"
#include "statedir/config_vectors.h"
#include "statedir/stored_problem.h"
#include "statespace/level_match.h"
#include "statespace/probe_model.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace hapstate {

// One undecided (source, direction) of an expandable configuration.
struct TransitionTask {
  Configuration source;
  Direction direction{0};
  Eigen::Vector3d from = Eigen::Vector3d::Zero();  // source check-point position, mesh units
  Eigen::Vector3d to = Eigen::Vector3d::Zero();    // neighbour position
  std::optional<CheckpointId> target;  // nullopt: the neighbour is outside the grid/workspace
};

// The outcome of solving one task (tasks without a target are not solved: move.ok is false
// and solved is false).
struct TransitionSolve {
  bool solved = false;
  bool trivial = false;  // contact: free to free at rest, no solve needed
  MoveResult move;
  ConfigVectors vectors;          // when move.ok
  std::array<double, 3> force{};  // felt by the user, N
  // Felt half-way through the move (directions with offsets >= 0, when that half converged).
  std::optional<std::array<double, 3>> midpoint_force;
  std::optional<std::array<double, 9>> midpoint_stiffness;  // the haptic stiffness there
  // The displacements there (mesh units) and their slopes d u / d p (3 columns), float32 as
  // stored; empty when there is no midpoint force.
  std::vector<float> midpoint_u;
  std::vector<float> midpoint_du_dp;
};

// Whether a move in `direction` stops half-way to record the force there (Transition::
// midpoint_force): the directions whose offsets are all >= 0, one per edge, face and cell of
// the grid seen from its lowest corner.
bool records_midpoint(Direction direction);

// The haptic stiffness of a configuration about to be stored (only new configurations need
// one: computing it for every solved transition would cost a factorisation each).
struct StiffnessTask {
  const ConfigVectors* vectors = nullptr;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // its check-point, mesh units
};
struct StiffnessResult {
  std::array<double, 9> stiffness{};  // row-major, N per mesh unit (0 if not computable)
  // d u / d p, dimensionless: 3 columns of one value per DOF, column (probe axis) after
  // column; stored as "<blob>/du_dp" for the Hermite deformation (0 where not computable).
  std::vector<float> du_dp;
  int factorisations = 0;
};

// The stiffness and derivative of PathSolver::haptic_stiffness as stored: non-finite entries
// as 0 (as the stiffness always was), so one failed configuration does not cost the whole
// playback file its slopes.
StiffnessResult stiffness_result(const Eigen::Matrix3d& stiffness, const Eigen::MatrixX3d& du_dp);
// The stiffness and displacement slopes of the body at rest, the probe at rest: the zero
// configurations' (they store no blob; one factorisation). The import computes it once and
// stores it with the problem (stored_rest_stiffness); zero_stiffness reads it.
RestStiffness rest_stiffness(const Problem& problem);
// The zero configurations' stiffness and slopes of a state directory: as its import stored them,
// or, for one imported before they were stored, computed (rest_stiffness).
RestStiffness zero_stiffness(const StateDir& dir, const Problem& problem);

// Who solves the expand stage's transitions. The stage hands it a wave's tasks (canonical
// order), then asks for the results of consecutive ranges of them (its batches), and for the
// stiffness of the configurations a batch creates before storing it.
class TransitionEngine {
 public:
  virtual ~TransitionEngine() = default;
  // The tasks of the next wave; the engine may keep a reference until the next call.
  virtual void start_wave(const std::vector<TransitionTask>& tasks) = 0;
  // The results of tasks [begin, end) of the wave; ranges come in order. An engine may solve
  // later tasks of the wave meanwhile, never at or past ahead_end (the stage's limit on
  // transitions ends the run there) nor past the wave.
  virtual std::vector<TransitionSolve> solve_range(std::size_t begin, std::size_t end,
                                                   std::size_t ahead_end) = 0;
  // The haptic stiffness of each task's state (set from the vectors, as a later move from that
  // configuration would); result k belongs to task k.
  virtual std::vector<StiffnessResult> stiffnesses(const std::vector<StiffnessTask>& tasks) = 0;
  // Time the solvers spent in assembly / factorisation / solves, summed over them (CPU-side
  // seconds, not wall time).
  virtual SolverTimings timings() const = 0;
  // For the stage run's parameters: how the work was distributed (e.g. "ranks=4"); "" for
  // threads in this process.
  virtual std::string parameters() const { return ""; }
  // How the work was shared, for the report (MPI: per-rank throughput and idle time); "" for
  // threads in this process. Complete after finish().
  virtual std::string summary() const { return ""; }
  // Releases the workers (an engine over MPI stops its ranks); results are no longer needed.
  virtual void finish() {}
};

struct StageContext;

// Makes the engine that solves the transitions (the expand stage's ExpandOptions::engine); called
// once the state directory is open and validated. Default: worker threads in this process.
using TransitionEngineFactory = std::function<std::unique_ptr<TransitionEngine>(
    const StageContext& ctx, const ProbeModel& probe, const BlobStore& blobs)>;

// How many consecutive tasks of one source a consumer (a thread, or an MPI worker with `least`
// threads) takes at once when `left` tasks of the window remain for `consumers` of them:
// whole sources (26 directions, times least) while much is left, down to `least` near the end
// of a wave (guided). Used by the thread pool and the MPI coordinator alike.
std::size_t guided_run(std::size_t left, std::size_t consumers, std::size_t least);

// Where a worker gets a source configuration's vectors from.
using SourceLoader = std::function<ConfigVectors(const Configuration&)>;
// From the state directory's blobs (load_config_vectors); keeps a reference to blobs.
SourceLoader blob_source_loader(const BlobStore& blobs, std::vector<double> rest_u,
                                const VectorLayout& layout);

// The transitions and stiffnesses on N threads of this process, each with its own PathSolver,
// kept running across batches and waves (a pool). solve_range() lets the threads run ahead of
// the batch asked for, up to a look-ahead window of the wave, so that they keep solving while
// the stage decides and stores the batch (docs/changelog.md, "Scaling"); stiffnesses() come
// first when both wait. Tasks are handed out in runs of one source's directions: a thread that
// solves several directions of a source in a row loads its vectors and factorises its tangent
// once (PathSolver's start factors). Each result is a pure function of its task, so which
// thread ran it, and when, changes nothing in the catalogue.
class TransitionSolver : public TransitionEngine {
 public:
  // Keeps references to problem and probe (they must outlive it). threads >= 1.
  TransitionSolver(const Problem& problem, const ProbeModel& probe, SourceLoader sources,
                   int threads, SolverAlgorithm algorithm = SolverAlgorithm::kFast);
  ~TransitionSolver() override;

  // Solves every task that has a target, in parallel; result k belongs to task k. An exception
  // in a worker (e.g. an unreadable source blob) is rethrown here after the pool stopped
  // taking work (the engine is then unusable).
  std::vector<TransitionSolve> solve(std::span<const TransitionTask> tasks);

  // Copies the wave's tasks (the threads may still run ahead on them after the stage let go).
  void start_wave(const std::vector<TransitionTask>& tasks) override;
  std::vector<TransitionSolve> solve_range(std::size_t begin, std::size_t end,
                                           std::size_t ahead_end) override;
  std::vector<StiffnessResult> stiffnesses(const std::vector<StiffnessTask>& tasks) override;
  // Complete after finish() (the threads' counters are read when they have stopped).
  SolverTimings timings() const override;
  // Stops and joins the threads (work under way ends at its current task).
  void finish() override;

  // How far past the requested batch the threads may run: enough work for each thread to
  // take a few whole sources, bounded so the solved results held meanwhile stay under about
  // 1 GiB (each holds its displacements and slopes).
  static std::size_t lookahead(int threads, int num_dofs);

 private:
  struct Pool;
  TransitionSolve solve_one(int worker, const TransitionTask& task);
  StiffnessResult stiffness_one(int worker, const StiffnessTask& task);
  // The source's vectors, read once for the directions of a source a worker solves in a row.
  const ConfigVectors& source_vectors(int worker, const Configuration& source);
  void worker_loop(int worker);
  void start_threads();
  // Waits (lock held) until `done` or a worker failed; rethrows a worker's exception.
  template <typename Done>
  void wait_for(std::unique_lock<std::mutex>& lock, Done&& done);

  const Problem& problem_;
  const ProbeModel& probe_;
  SourceLoader sources_loader_;
  int threads_;
  SolverAlgorithm algorithm_;
  std::vector<std::unique_ptr<PathSolver>> solvers_;  // one per worker, created on first use
  struct LoadedSource {
    Configuration config;
    ConfigVectors vectors;
  };
  std::vector<std::optional<LoadedSource>> sources_;  // per worker: the last source read
  std::unique_ptr<Pool> pool_;
};

}  // namespace hapstate
