// The parallel part of the expand stage: solving a batch of transitions on N worker threads,
// one PathSolver per worker (kept across batches). Each solve is a pure function of the
// source configuration's stored vectors and the direction, so the results do not depend on
// the thread count or on which worker ran them.
#pragma once

#include "blobs/blob_store.h"
#include "catalogue/records.h"
#include "solver/path_solver.h"
#include "statespace/level_match.h"
#include "statespace/probe_model.h"

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
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
  bool trivial = false;               // contact: free to free at rest, no solve needed
  MoveResult move;
  ConfigVectors vectors;              // when move.ok
  std::array<double, 3> force{};      // felt by the user, N
  std::array<double, 9> stiffness{};  // row-major, N per mesh unit (0 if not computable)
};

// The vectors of a stored configuration: from its blob, or zeros for one without a blob (the
// zero configuration: nothing touched), laid out as `layout` says (the touched set read from
// <name>/touched where it is stored). Throws InputError naming the segment and vector if they
// cannot be read or have the wrong sizes.
ConfigVectors load_config_vectors(const BlobStore& blobs, const Configuration& c, int num_dofs,
                                  const VectorLayout& layout);

class TransitionSolver {
 public:
  // Keeps references to problem, probe and blobs (they must outlive it). threads >= 1.
  TransitionSolver(const Problem& problem, const ProbeModel& probe, const BlobStore& blobs,
                   int threads);
  ~TransitionSolver();

  // Solves every task that has a target, in parallel; result k belongs to task k. An exception
  // in a worker (e.g. an unreadable source blob) is rethrown here after all workers stopped.
  std::vector<TransitionSolve> solve(const std::vector<TransitionTask>& tasks);
  // Time the workers' solvers spent in assembly / factorisation / solves, summed over workers
  // (CPU-side seconds, not wall time).
  SolverTimings timings() const;

 private:
  TransitionSolve solve_one(PathSolver& solver, const TransitionTask& task);

  const Problem& problem_;
  const ProbeModel& probe_;
  const BlobStore& blobs_;
  int threads_;
  std::vector<std::unique_ptr<PathSolver>> solvers_;  // one per worker, created on first use
};

}  // namespace hapstate
