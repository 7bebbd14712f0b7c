// The precise path solver (the paper's "precise method"): keeps an equilibrium state of the
// body and moves the probe to a new position by incremental-load predictor steps and Newton
// corrections, with line search, cut-back and a recorded failure reason instead of an abort.
//
// Units: probe displacements t and positions are in mesh units (as in the scene); internally
// the FEM works in metres (mesh units x Problem::unit); forces are in N.
// Sign: force_felt() is the force the user feels, -sum over probe DOFs of the internal force
// (h = dPi/du_P is the force the probe applies to the body; the user feels its opposite).
// Not thread-safe: one PathSolver per thread.
#pragma once

#include "fem/assembler.h"
#include "scene/problem.h"
#include "solver/sparse_cholesky.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace hapstate {

enum class SolveFailure {
  kNone = 0,
  kMaxIterations = 1,   // Newton did not reach the tolerance within max_iterations
  kInverted = 2,        // every trial step inverted an element (J <= 0)
  kNotFinite = 3,       // NaN or infinity in the residual
  kLineSearch = 4,      // no step along the Newton direction reduced energy or residual
  kCutbackLimit = 5,    // the sub-step was halved max_cutbacks times and still failed
};
const char* failure_name(SolveFailure f);

struct MoveResult {
  bool ok = true;
  SolveFailure failure = SolveFailure::kNone;
  std::string reason;            // human-readable failure reason (empty if ok)
  int substeps = 0;              // accepted sub-steps
  int cutbacks = 0;              // sub-step halvings
  int iterations = 0;            // Newton iterations (factorisations) over the whole move
  double residual = 0;           // final ||r_free|| [N]
  double wall_ms = 0;
  std::vector<double> residual_history;  // ||r_free|| of the last Newton solve, per iteration
};

// Cumulative time spent in each phase (seconds) and counts, for benchmarks.
struct SolverTimings {
  double assembly = 0, factorize = 0, solve = 0, analyze = 0;
  long long assemblies = 0, factorizations = 0, psd_fallbacks = 0;
};

class PathSolver {
 public:
  explicit PathSolver(const Problem& problem);
  ~PathSolver();

  int num_dofs() const;
  // Back to the rest state (u = 0, t = 0).
  void reset();
  // Moves the probe to displacement t_target (mesh units, relative to Problem::probe_rest)
  // from the current state. On failure the state is left at the start of the move.
  MoveResult move_to(const Eigen::Vector3d& t_target);

  Eigen::Vector3d probe_displacement() const { return t_; }  // mesh units
  // Displacement of every node, mesh units (3 x num_nodes).
  Eigen::Matrix3Xd displacements() const;
  // Raw state vector (metres, DOF order 3*node + component) and its setter.
  const Eigen::VectorXd& state_m() const { return u_; }
  void set_state(const Eigen::VectorXd& u_m, const Eigen::Vector3d& t);
  // Force felt by the user [N] at the current state.
  Eigen::Vector3d force_felt() const;
  // Reactions h at the probe DOFs [N]: the internal force the body resists the probe with, one
  // value per probe DOF in ascending DOF order (force_felt() is minus their per-component sum).
  // One force assembly.
  Eigen::VectorXd probe_reactions() const;
  // d force_felt / d probe position [N per mesh unit] at the current state (one extra
  // assembly and factorisation; the reduced-stiffness Schur complement on the probe DOFs).
  Eigen::Matrix3d haptic_stiffness();

  const SolverTimings& timings() const { return timings_; }
  const SparseCholesky& linear_solver() const { return *cholesky_; }
  const SolverOptions& options() const { return options_; }

 private:
  struct Newton;
  bool substep(const Eigen::Vector3d& t_from, const Eigen::Vector3d& t_to, double rel_tol,
               MoveResult* result);
  bool newton(double rel_tol, MoveResult* result);
  void assemble(const Eigen::VectorXd& u, bool project_psd, double* energy);
  void constrain_values();
  bool factorize_with_fallback(const Eigen::VectorXd& u);
  void set_probe_dofs(const Eigen::Vector3d& t, Eigen::VectorXd* u) const;
  double free_norm(const Eigen::VectorXd& v) const;
  double reaction_norm(const Eigen::VectorXd& f) const;

  std::unique_ptr<Material> material_;
  std::unique_ptr<Assembler> assembler_;
  std::unique_ptr<SparseCholesky> cholesky_;
  std::vector<DofRole> role_;
  std::vector<int> probe_dof_component_;  // per DOF: component 0..2 if probe DOF, else -1
  double unit_;
  int num_nodes_;
  SolverOptions options_;
  SolverTimings timings_;

  Eigen::VectorXd u_;       // metres
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();  // mesh units
  // Workspace.
  Eigen::VectorXd f_, r_, du_, trial_, f_trial_;
  std::vector<double> k_values_;
};

}  // namespace hapstate
