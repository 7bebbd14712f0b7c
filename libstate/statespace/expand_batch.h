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
};

// The haptic stiffness of a configuration about to be stored (only new configurations need
// one: computing it for every solved transition would cost a factorisation each).
struct StiffnessTask {
  const ConfigVectors* vectors = nullptr;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // its check-point, mesh units
};
struct StiffnessResult {
  std::array<double, 9> stiffness{};  // row-major, N per mesh unit (0 if not computable)
  int factorisations = 0;
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
                   int threads, SolverAlgorithm algorithm = SolverAlgorithm::kFast);
  ~TransitionSolver();

  // Solves every task that has a target, in parallel; result k belongs to task k. An exception
  // in a worker (e.g. an unreadable source blob) is rethrown here after all workers stopped.
  std::vector<TransitionSolve> solve(const std::vector<TransitionTask>& tasks);
  // The haptic stiffness of each task's state, in parallel (the state is set from the vectors,
  // as a later move from that configuration would).
  std::vector<StiffnessResult> stiffnesses(const std::vector<StiffnessTask>& tasks);
  // Time the workers' solvers spent in assembly / factorisation / solves, summed over workers
  // (CPU-side seconds, not wall time).
  SolverTimings timings() const;

 private:
  TransitionSolve solve_one(int worker, const TransitionTask& task);
  // The source's vectors, read once for the directions of a source a worker solves in a row.
  const ConfigVectors& source_vectors(int worker, const Configuration& source);
  // Runs body(worker, k) for k in [0, count) on the workers (each with its own solver).
  template <typename Body>
  void for_each_parallel(std::size_t count, Body&& body);

  const Problem& problem_;
  const ProbeModel& probe_;
  const BlobStore& blobs_;
  int threads_;
  SolverAlgorithm algorithm_;
  std::vector<std::unique_ptr<PathSolver>> solvers_;  // one per worker, created on first use
  struct LoadedSource {
    Configuration config;
    ConfigVectors vectors;
  };
  std::vector<std::optional<LoadedSource>> sources_;  // per worker: the last source read
};

}  // namespace hapstate
