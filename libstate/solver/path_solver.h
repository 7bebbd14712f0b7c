// The precise path solver (the paper's "precise method"): keeps an equilibrium state of the
// body and moves the probe to a new position by incremental-load predictor steps and Newton
// corrections, with line search, cut-back and a recorded failure reason instead of an abort.
//
// Units: probe displacements t and positions are in mesh units (as in the scene); internally
// the FEM works in metres (mesh units x Problem::unit); forces are in N.
// Sign: force_felt() is the force the user feels, -sum over probe DOFs of the internal force
// (h = dPi/du_P is the force the probe applies to the body; the user feels its opposite).
// Contact probe (Problem::contact): the probe is a rigid sphere and t the displacement of its
// centre (docs/contact.md). What differs between the grab, the frictionless and the sticking
// probe (prescribed DOFs, the sphere's energy, the active set settled after each Newton solve)
// is the ProbeBoundary's (solver/probe_boundary.h); the solver never asks which probe it has.
// Not thread-safe: one PathSolver per thread.
#pragma once

#include "fem/assembler.h"
#include "problem/problem.h"
#include "solver/contact_set.h"
#include "solver/move_result.h"
#include "solver/probe_boundary.h"
#include "solver/sparse_cholesky.h"

#include <Eigen/Core>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace hapstate {

// Cumulative time spent in each phase (seconds) and counts, for benchmarks.
struct SolverTimings {
  double assembly = 0, factorize = 0, solve = 0, analyze = 0;
  long long assemblies = 0, factorisations = 0;
  long long psd_fallbacks = 0;     // PSD-projected tangents factorised or solved with by CG
  long long inner_iterations = 0;  // conjugate-gradient iterations of the inexact Newton
  // Solves with a factor (forward and backward substitution: each reads the whole factor), and
  // the largest factor's size in bytes (SparseCholesky::factor_bytes; a maximum, not a sum).
  long long back_substitutions = 0, single_back_substitutions = 0;  // the second: of the first
  double factor_bytes = 0, single_factor_bytes = 0;                 // the second: rounded
  // Contact probe: collision detection (summed by TransitionSolver::timings from
  // PathSolver::contact_timings; PathSolver::timings leaves them 0).
  double contact_detection = 0;
  long long contact_queries = 0;

  // Adds every field of `other` (sums over solvers, threads or ranks).
  SolverTimings& operator+=(const SolverTimings& other) {
    assembly += other.assembly;
    factorize += other.factorize;
    solve += other.solve;
    analyze += other.analyze;
    assemblies += other.assemblies;
    factorisations += other.factorisations;
    psd_fallbacks += other.psd_fallbacks;
    inner_iterations += other.inner_iterations;
    back_substitutions += other.back_substitutions;
    single_back_substitutions += other.single_back_substitutions;
    factor_bytes = factor_bytes > other.factor_bytes ? factor_bytes : other.factor_bytes;
    single_factor_bytes = single_factor_bytes > other.single_factor_bytes
                              ? single_factor_bytes
                              : other.single_factor_bytes;
    contact_detection += other.contact_detection;
    contact_queries += other.contact_queries;
    return *this;
  }
};

class PathSolver {
 public:
  explicit PathSolver(const Problem& problem);
  ~PathSolver();

  int num_dofs() const;
  // Back to the rest state (u = Problem::rest_m, or 0 without loads; t = 0).
  void reset();
  // Finds the equilibrium under the problem's body loads (Problem::loads) from the current
  // state by incremental loading: the body force scaled up from 0 to 1 in steps (a quarter
  // first, doubled after an easy step, halved after a failed one, down to 1/4096), each
  // converged by Newton with the move's safeguards (line search, PSD fallback). The probe stays
  // where it is (solver/rest_state.h frees it first). On failure the state is the last
  // converged one and the load scale is left there.
  MoveResult settle_under_loads();
  // Moves the probe to displacement t_target (mesh units, relative to Problem::probe_rest)
  // from the current state. A move that fails is tried again as 4, then 16 equal moves, each
  // converged to the full tolerance (MoveResult::split_pieces; the counts of the failed
  // attempts are included). On failure the state is left at the start of the move.
  MoveResult move_to(const Eigen::Vector3d& t_target);

  Eigen::Vector3d probe_displacement() const { return t_; }  // mesh units
  // Displacement of every node, mesh units (3 x num_nodes).
  Eigen::Matrix3Xd displacements() const;
  // The loaded rest state (Problem::rest_m, or zeros), metres.
  const Eigen::VectorXd& rest_state_m() const { return rest_; }
  // Raw state vector (metres, DOF order 3*node + component) and its setter.
  const Eigen::VectorXd& state_m() const { return u_; }
  // Sticking contact: `touched` are the nodes the sphere holds in that state (anchors are taken
  // from u_m); without it, the touched set is empty. Frictionless contact: `multipliers` are the
  // state's contact multipliers (contact_multipliers() of the state; without them, zero: the
  // next move then rebuilds the contact forces). Throws InputError for a touched node that is
  // not a candidate or multipliers that do not fit the mesh.
  void set_state(const Eigen::VectorXd& u_m, const Eigen::Vector3d& t,
                 const std::vector<int>& touched = {}, const std::vector<double>& multipliers = {});
  // Frictionless contact: the non-zero multipliers, pairs (surface triangle, N); else empty.
  std::vector<double> contact_multipliers() const { return boundary_->stored_multipliers(); }
  // Contact mode: the nodes the sphere holds (sticking) or presses (frictionless: the corners
  // of the loaded triangles), ascending (empty in grab mode).
  std::vector<int> touched_nodes() const { return boundary_->touched_nodes(u_, t_); }
  // Contact mode: collision-detection cost so far (nullptr in grab mode).
  const ContactTimings* contact_timings() const { return boundary_->timings(); }
  // Force felt by the user [N] at the current state.
  Eigen::Vector3d force_felt() const;
  // Reactions h at the probe DOFs [N]: the internal force the body resists the probe with, one
  // value per probe DOF in ascending DOF order (force_felt() is minus their per-component sum).
  // After a successful grab move, the converged Newton's force; else one force assembly.
  Eigen::VectorXd probe_reactions() const;
  // d force_felt / d probe position [N per mesh unit] at the current state (one extra
  // assembly and factorisation; the reduced-stiffness Schur complement on the probe DOFs).
  // du_dp, if given, receives the displacement's derivative with respect to the probe
  // position at equilibrium: column c = d u / d p_c, one row per DOF, dimensionless (the
  // back-substitutions of the Schur complement give it at no extra factorisation).
  // keep_factor: a move from this state follows (a midpoint's second half): its factorisation
  // is kept for that move's predictor, which then needs none of its own.
  Eigen::Matrix3d haptic_stiffness(Eigen::MatrixX3d* du_dp = nullptr, bool keep_factor = false);

  const SolverTimings& timings() const { return timings_; }
  const SparseCholesky& linear_solver() const { return *cholesky_; }
  const SolverOptions& options() const { return options_; }
  void set_algorithm(SolverAlgorithm algorithm) { options_.algorithm = algorithm; }
  // Threads for the element assembly inside this solver (default 1; the results do not depend
  // on it). The BLAS threads of the factorisation are the process's (statespace/math_threads.h).
  void set_threads(int threads) { assembler_->set_threads(threads); }

 private:
  // One move: sub-steps with cut-backs; on failure the state is left at the start.
  MoveResult move_once(const Eigen::Vector3d& t_target);
  struct StartState;
  StartState start_state() const;
  void restore(const StartState& start);
  class Host;  // the SettleHost the boundary's settling works through
  // Roles, probe components and bases: the scene's, then the boundary's probe DOFs.
  void apply_prescription();
  bool substep(const Eigen::Vector3d& t_from, const Eigen::Vector3d& t_to, double rel_tol,
               bool move_start, MoveResult* result);
  // have_factor: factor_ is of a nearby state (the predictor's) and may precondition the
  // inexact Newton's first solve.
  bool newton(double rel_tol, MoveResult* result, bool have_factor = false);
  enum class CgOutcome { kConverged, kNotConverged, kNegativeCurvature };
  CgOutcome preconditioned_cg();
  // The predictor of a sub-step from (u_, t_from) for the probe step dt: f_, K dt and the
  // factor of the tangent there. Inexact Newton keeps the factor of a move's start state in
  // one of start_factors_ and reuses it (and its f and K) when the next move starts from the same
  // state, as every direction of a configuration's expansion does.
  bool predictor_factor(const Eigen::Vector3d& t_from, const Eigen::VectorXd& dt, bool move_start,
                        Eigen::VectorXd* k_dt, MoveResult* result);
  bool inexact_newton() const {
    return options_.algorithm == SolverAlgorithm::kFast && boundary_->allows_inexact_newton();
  }
  void assemble(const Eigen::VectorXd& u, bool project_psd, double* energy);
  // A probe with its own energy (frictionless contact): k_values_ = the elastic tangent of the
  // last assemble() + the probe's tangent at u (psd_only: its positive semi-definite part).
  // False (nothing changed) if that assembly kept no elastic tangent.
  bool probe_tangent_on_elastic(const Eigen::VectorXd& u, bool psd_only);
  void constrain_values();
  bool factorize_with_fallback(const Eigen::VectorXd& u, SparseCholesky* target);
  // x = factor^{-1} b (single: with the factor rounded to float, SparseCholesky::solve_single),
  // counted in timings_.back_substitutions.
  void back_substitute(SparseCholesky& factor, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                       bool single = false);
  void set_probe_dofs(const Eigen::Vector3d& t, Eigen::VectorXd* u) const;
  void set_probe_translation(const Eigen::Vector3d& dt, Eigen::VectorXd* v) const;
  // The largest displacement of one node in du [m].
  double longest_node_step(const Eigen::VectorXd& du) const;
  double free_norm(const Eigen::VectorXd& v) const;
  double reaction_norm(const Eigen::VectorXd& f) const;
  double total_energy_and_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const;
  // The internal force at u_: state_force_ when valid, else assembled into *scratch.
  const Eigen::VectorXd& state_force(Eigen::VectorXd* scratch) const;

  std::unique_ptr<Material> material_;
  std::unique_ptr<Assembler> assembler_;
  std::unique_ptr<SparseCholesky> cholesky_;
  SparseCholesky* factor_ = nullptr;  // the factor Newton solves with
  // Inexact Newton: the factors of recent move starts (predictor_factor), with the state each
  // factorises and f and the tangent's values there; last_use orders them for replacement.
  struct StartFactor {
    std::unique_ptr<SparseCholesky> cholesky;
    bool valid = false;
    Eigen::VectorXd u, f;
    BoundaryState boundary;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    std::vector<double> k;
    long long last_use = 0;
  };
  std::array<StartFactor, 2> start_factors_;
  // The kept factor of the state (u_, t, the boundary's), if any.
  StartFactor* kept_start_factor(const Eigen::Vector3d& t);
  // The slot to keep the factor of (u_, t) in (the least recently used), holding that state,
  // f_ and the unconstrained tangent in k_values_; valid once the caller's factorisation
  // succeeded.
  StartFactor& start_factor_to_fill(const Eigen::Vector3d& t);
  long long start_factor_uses_ = 0;
  // Grab probe (ProbeBoundary::keeps_newton_force): the force at u_ after a successful move
  // (the converged Newton's), so that
  // force_felt() and probe_reactions() need no assembly; invalid after any other change of u_.
  bool state_force_valid_ = false;
  Eigen::VectorXd state_force_;
  std::unique_ptr<ProbeBoundary> boundary_;
  Prescription scene_;  // the scene's roles (nodes used by no tet fixed), no probe component
  Prescription now_;    // scene_ with the boundary's probe DOFs in the current state

  double unit_;
  int num_nodes_;
  BodyLoads loads_;       // the problem's (the assembler points at it)
  Eigen::VectorXd rest_;  // Problem::rest_m, or zeros
  SolverOptions options_;
  SolverTimings timings_;

  Eigen::VectorXd u_;                                  // metres
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();        // mesh units
  Eigen::Vector3d t_solve_ = Eigen::Vector3d::Zero();  // the probe of the solve under way
  // Workspace.
  Eigen::VectorXd f_, r_, du_, trial_, f_trial_;
  Eigen::VectorXd cg_r_, cg_z_, cg_p_, cg_q_;
  std::vector<double> k_values_;
  // A probe with its own energy: the elastic part of the last non-projected assembly, whose
  // probe part alone is projected first when the tangent is indefinite (the probe's curvature
  // term is what makes it so, almost always; the elastic projection costs an eigen-decomposition
  // per element).
  std::vector<double> k_elastic_;
  bool k_elastic_valid_ = false;
};

}  // namespace hapstate
