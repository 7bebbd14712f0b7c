#include "solver/path_solver.h"

#include "util/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace hapstate {
namespace {

using Clock = std::chrono::steady_clock;

std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", v);
  return buf;
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Intermediate sub-steps only need to stay close to the equilibrium path; the final
// sub-step is solved to the user's tolerance.
constexpr double kIntermediateRelTol = 1e-2;
// Inexact Newton (SolverAlgorithm::kFast): conjugate gradients preconditioned by a kept
// factorisation solve each Newton system to this relative residual, in at most this many
// iterations, else the tangent is factorised afresh. Measured on the liver's complete expansion
// (2 threads; wall s, factorisations and CG iterations per solved transition): tolerance 1e-2 /
// 1e-3 / 1e-4 with 25 iterations 27.5 / 27.5 / 29.2 s; 8 / 15 / 50 iterations with 1e-2
// 27.2 s, 1.38, 29.7 / 26.0 s, 0.60, 45.5 / 27.3 s, 0.42, 54.4; liverSemiFine's first 256
// transitions 15 / 50 iterations: 17.5 / 18.4 transitions/s (full Newton: 4.6). 40, between the
// two best, keeps the factorisations low on the larger meshes, where one costs most.
constexpr double kInexactTolerance = 1e-2;
constexpr int kMaxInnerIterations = 40;
// Newton goes on past SolverOptions::max_iterations while it still converges steadily: the
// residual at least halved over the last kProgressWindow iterations, up to kMaxIterationFactor x
// max_iterations in all. Nearly incompressible bodies (nu >= 0.499) under large strain converge
// only linearly for a while (an ill-conditioned tangent, CG to 1e-2 with a kept preconditioner,
// PSD-projected tangents where it is indefinite) and need 35-90 iterations; cutting the
// sub-step back does not help when it is the move's last (it must reach the full tolerance
// whatever its size). Measured with hapstate-stress (docs/benchmarks.md): 9 cases that failed
// with max_iterations in one move but converged in moves of a quarter grid spacing now converge
// as asked. A solve that stalls or diverges still fails at max_iterations.
constexpr int kProgressWindow = 10;
constexpr double kProgressFactor = 0.5;
constexpr int kMaxIterationFactor = 4;
// Armijo sufficient-decrease constant and line-search halvings.
constexpr double kArmijo = 1e-4;
constexpr int kMaxLineSearch = 12;
// Frictionless contact: the penalty k of the augmented Lagrangian is
// SolverOptions::contact_penalty x the median diagonal stiffness of the free surface DOFs at
// rest (past nu = 0.45, x incompressible_share below). A stiff penalty turns the small
// linearisation error of a sliding sub-step into a large residual (more Newton iterations,
// line-search cuts and failed moves); a soft one needs more multiplier updates (nearly redundant
// gaps of faces wrapped around the sphere contract slowly). Measured: the plate's pressing and
// sliding moves (factorisations over a 7-move path) 100x 179, 300x 198, 1000x 271; the liver's 3-D
// expansion 300x 10 failed moves of 14 896, 1000x over 117 (and slower); the block's pressing moves
// need up to 8 updates with 100x, 2-3 with 300x. When a multiplier update shrinks the largest gap
// violation by less than kSlowContraction, the penalty grows by kPenaltyGrowth for the rest of the
// sub-step (at most kMaxPenaltyScale x k): the standard augmented-Lagrangian remedy for slow
// contraction. Measured on the plate of 20 x 20 cells (0.2 cm), 1 558 solved moves: 8 failed with
// the gaps 1.1-1.3e-6 r from closed after 20 updates, 0 with the growth.
constexpr double kSlowContraction = 0.5;
constexpr double kPenaltyGrowth = 4.0;
constexpr double kMaxPenaltyScale = 64.0;
// The haptic stiffness treats the active gaps with this multiple of k, as the exact
// constraints they converge to.
constexpr double kStiffnessPenaltyFactor = 1e3;
// A frictionless sub-step moves the sphere by at most this fraction of its radius, so that
// nothing can pass through it between two solves and each Newton solve starts with the
// penetrated triangles on the near side of the centre.
constexpr double kMaxStepPerRadius = 0.5;

// The share of the contact penalty's stiffness scale (surface_stiffness) that resists an
// indentation. The diagonal of the tangent grows with the P-wave modulus M = K + 4/3 mu, which
// for a nearly incompressible body is almost all bulk modulus K (M / mu = 2(1 - nu) / (1 - 2 nu):
// 3.5 at nu 0.3, 11 at 0.45, 501 at 0.499); an indentation changes shape, not volume, and is
// resisted by mu. Past nu = 0.45 (M / mu > kMaxWaveToShear) the scale is taken as
// kMaxWaveToShear x mu instead, so the penalty stops growing with K: measured on a bar pressed by
// a sphere (hapstate-stress), 300x the diagonal failed every contact case at nu 0.4999 (line
// search, also in moves of a quarter grid spacing) and converged with it. Up to nu = 0.45 (the
// bundled scenes, where the 300x was measured) the penalty is unchanged.
constexpr double kMaxWaveToShear = 11.0;
double incompressible_share(const MaterialConstants& m) {
  double mu = 0, bulk = 0;
  switch (m.law) {
    case Law::kLinear:
    case Law::kStvk:
      mu = m.mu;
      bulk = m.lambda + 2.0 / 3.0 * m.mu;
      break;
    case Law::kNeoHooke:
      mu = 2 * m.c10;
      bulk = 2 / m.d1;
      break;
    case Law::kMooney:
      mu = 2 * (m.c10 + m.c01);
      bulk = 2 / m.d1;
      break;
  }
  const double wave = bulk + 4.0 / 3.0 * mu;
  // (A relative margin keeps nu = 0.45 itself, whose M / mu = 11 up to rounding, at exactly 1.)
  if (!(mu > 0) || !(wave > kMaxWaveToShear * mu * (1 + 1e-9))) return 1.0;
  return kMaxWaveToShear * mu / wave;
}

// The median of the diagonal of the elastic tangent at rest over the free DOFs of the surface
// nodes [N/m]: the stiffness scale of the contact penalty.
double surface_stiffness(const Assembler& assembler, const Mesh& mesh,
                         const std::vector<DofRole>& role) {
  Eigen::VectorXd f;
  std::vector<double> k;
  assembler.energy_force_tangent(Eigen::VectorXd::Zero(assembler.num_dofs()), &f, &k);
  std::vector<double> diag;
  for (int t = 0; t < mesh.surface.cols(); ++t)
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) {
        const int d = 3 * mesh.surface(i, t) + c;
        if (role[d] == DofRole::kFree) diag.push_back(k[assembler.pattern().diag[d]]);
      }
  if (diag.empty()) return 1.0;
  std::nth_element(diag.begin(), diag.begin() + diag.size() / 2, diag.end());
  return diag[diag.size() / 2];
}

}  // namespace

const char* failure_name(SolveFailure f) {
  switch (f) {
    case SolveFailure::kNone:
      return "none";
    case SolveFailure::kMaxIterations:
      return "max_iterations";
    case SolveFailure::kInverted:
      return "inverted_element";
    case SolveFailure::kNotFinite:
      return "not_finite";
    case SolveFailure::kLineSearch:
      return "line_search";
    case SolveFailure::kCutbackLimit:
      return "cutback_limit";
    case SolveFailure::kContactCycle:
      return "contact_cycle";
    case SolveFailure::kContactUnsettled:
      return "contact_unsettled";
  }
  return "unknown";
}

PathSolver::PathSolver(const Problem& problem)
    : material_(make_material(problem.material)),
      role_(problem.constraints.role),
      unit_(problem.unit),
      num_nodes_(problem.mesh.num_nodes()),
      options_(problem.solver) {
  const Eigen::Matrix3Xd positions_m = problem.mesh.nodes * unit_;
  assembler_ = std::make_unique<Assembler>(positions_m, problem.mesh.tets, *material_);
  cholesky_ = std::make_unique<SparseCholesky>(assembler_->pattern());
  factor_ = cholesky_.get();
  timings_.analyze = cholesky_->analyze_seconds();
  // Nodes used by no tet have no stiffness: hold them where they are.
  std::vector<bool> used(num_nodes_, false);
  for (int e = 0; e < problem.mesh.num_tets(); ++e)
    for (int a = 0; a < 4; ++a) used[problem.mesh.tets(a, e)] = true;
  for (int n = 0; n < num_nodes_; ++n)
    if (!used[n])
      for (int c = 0; c < 3; ++c) role_[3 * n + c] = DofRole::kFixed;
  probe_dof_component_.assign(3 * num_nodes_, -1);
  for (int n : problem.constraints.probe_nodes)
    for (int c = 0; c < 3; ++c)
      if (role_[3 * n + c] == DofRole::kProbe) probe_dof_component_[3 * n + c] = c;
  base_role_ = role_;
  probe_base_.setZero(num_dofs());
  probe_rest_ = problem.probe_rest;
  if (problem.contact && problem.contact->friction == Friction::kStick) {
    contact_ = std::make_unique<ContactSet>(problem.mesh.nodes, *problem.contact, probe_rest_);
  } else if (problem.contact) {
    const double penalty = options_.contact_penalty * incompressible_share(problem.material) *
                           surface_stiffness(*assembler_, problem.mesh, role_);
    sliding_ = std::make_unique<SlidingContact>(positions_m, problem.mesh.surface,
                                                problem.contact->radius * unit_, penalty,
                                                assembler_->pattern());
  }
  reset();
}

PathSolver::~PathSolver() = default;

int PathSolver::num_dofs() const { return assembler_->num_dofs(); }

void PathSolver::reset() {
  u_.setZero(num_dofs());
  state_force_valid_ = false;
  t_.setZero();
  t_solve_.setZero();
  if (sliding_) sliding_->reset_multipliers();
  if (contact_) {
    contact_->clear();
    apply_contact_roles();
  }
}

void PathSolver::set_state(const Eigen::VectorXd& u_m, const Eigen::Vector3d& t,
                           const std::vector<int>& touched,
                           const std::vector<double>& multipliers) {
  if (sliding_ && !sliding_->set_sparse_multipliers(multipliers))
    throw InputError("contact multipliers: expected pairs (surface triangle index, value >= 0)");
  u_ = u_m;
  t_ = t;
  t_solve_ = t;
  state_force_valid_ = false;
  if (!contact_) return;
  contact_->assign(touched, u_, unit_, probe_rest_ + t_);
  apply_contact_roles();
}

std::vector<int> PathSolver::touched_nodes() const {
  if (sliding_) return sliding_->touched_nodes(u_, centre_m(t_));
  return contact_ ? contact_->touched() : std::vector<int>{};
}

const ContactTimings* PathSolver::contact_timings() const {
  if (sliding_) {
    sliding_timings_.detection = sliding_->detection_seconds();
    sliding_timings_.queries = sliding_->queries();
    return &sliding_timings_;
  }
  return contact_ ? &contact_->timings() : nullptr;
}

double PathSolver::total_energy_and_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const {
  double e = assembler_->energy_and_force(u, f);
  if (sliding_ && std::isfinite(e)) e += sliding_->add_force(u, centre_m(t_solve_), f);
  return e;
}

// Frictionless contact after a Newton solve at t_solve_: the multiplier updates. An intermediate
// sub-step only updates them (a warm start for the next); the final one re-solves until every
// gap is closed to options_.gap_tolerance x radius. Nothing touched: the body is at rest, exactly.
bool PathSolver::settle_sliding(double rel_tol, bool last, MoveResult* result) {
  const Eigen::Vector3d centre = centre_m(t_solve_);
  const double tolerance = options_.gap_tolerance * sliding_->radius();
  if (!last) sliding_->update_multipliers(u_, centre);
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 0; last; ++it) {
    const double violation = sliding_->violation(u_, centre);
    if (violation <= tolerance) break;
    // Nearly redundant gaps (faces wrapped around the sphere) contract slowly: stiffen k.
    if (violation > kSlowContraction * previous && sliding_->penalty_scale() < kMaxPenaltyScale)
      sliding_->set_penalty_scale(sliding_->penalty_scale() * kPenaltyGrowth);
    previous = violation;
    if (it >= options_.max_active_set_iterations) {
      result->failure = SolveFailure::kContactUnsettled;
      result->reason = "the contact gaps were still " + sci(violation / sliding_->radius()) +
                       " x radius from closed after " +
                       std::to_string(options_.max_active_set_iterations) + " multiplier updates";
      return false;
    }
    sliding_->update_multipliers(u_, centre);
    ++result->active_set_iterations;
    if (!newton(rel_tol, result, /*have_factor=*/true)) return false;  // the last solve's
  }
  if (!sliding_->any_active(u_, centre)) {
    u_.setZero();
    sliding_->reset_multipliers();
  }
  return true;
}

// Contact mode: the touched nodes become probe DOFs (all three components) that follow the
// sphere centre, u = probe_base_ + t with probe_base_ = centre_rest + anchor - X.
void PathSolver::apply_contact_roles() {
  role_ = base_role_;
  std::fill(probe_dof_component_.begin(), probe_dof_component_.end(), -1);
  const std::vector<int>& touched = contact_->touched();
  for (std::size_t k = 0; k < touched.size(); ++k) {
    const Eigen::Vector3d base = contact_->prescribed(static_cast<int>(k), probe_rest_);
    for (int c = 0; c < 3; ++c) {
      const int d = 3 * touched[k] + c;
      role_[d] = DofRole::kProbe;
      probe_dof_component_[d] = c;
      probe_base_[d] = base[c] * unit_;
    }
  }
}

// The active-set loop at probe displacement t, from an equilibrium (f_ assembled at u_):
// release adhesive touched nodes, add penetrating ones, re-solve, until the set is stable.
bool PathSolver::settle_contact(const Eigen::Vector3d& t, double rel_tol, MoveResult* result) {
  const Eigen::Vector3d centre = probe_rest_ + t;
  // A set repeats when the same nodes come back with the same anchors: a node released and
  // re-added from where it sprang back gets a new anchor (it slides along the sphere) and is
  // progress, not a cycle.
  const double same_anchor = 1e-9 * contact_->radius();
  auto same = [&](const ContactSet::Held& a, const ContactSet::Held& b) {
    if (a.nodes != b.nodes) return false;
    for (std::size_t k = 0; k < a.anchors.size(); ++k)
      if ((a.anchors[k] - b.anchors[k]).norm() > same_anchor) return false;
    return true;
  };
  std::vector<ContactSet::Held> seen{contact_->held()};
  for (int it = 0;; ++it) {
    const ContactChange change =
        contact_->decide(u_, unit_, f_, centre, options_.absolute_tolerance);
    if (change.empty()) return true;
    if (it >= options_.max_active_set_iterations) {
      result->failure = SolveFailure::kContactUnsettled;
      result->reason = "the touched set still changed after " +
                       std::to_string(options_.max_active_set_iterations) +
                       " active-set iterations (" + std::to_string(change.added.size()) +
                       " node(s) to add, " + std::to_string(change.released.size()) +
                       " to release)";
      return false;
    }
    contact_->apply(change, u_, unit_, centre);
    ++result->active_set_iterations;
    const ContactSet::Held now = contact_->held();
    if (std::any_of(seen.begin(), seen.end(),
                    [&](const ContactSet::Held& h) { return same(h, now); })) {
      std::string nodes;
      for (int n : change.added) nodes += " +" + std::to_string(n);
      for (int n : change.released) nodes += " -" + std::to_string(n);
      result->failure = SolveFailure::kContactCycle;
      result->reason = "the touched set oscillates: after" + nodes +
                       " it is a set (nodes and anchors) it already had in this sub-step";
      return false;
    }
    seen.push_back(now);
    apply_contact_roles();
    if (contact_->touched().empty()) {
      // Nothing loads the body: it is at rest (exactly).
      u_.setZero();
      continue;
    }
    set_probe_dofs(t, &u_);
    if (!newton(rel_tol, result)) return false;
  }
}

Eigen::Matrix3Xd PathSolver::displacements() const {
  return Eigen::Map<const Eigen::Matrix3Xd>(u_.data(), 3, num_nodes_) / unit_;
}

void PathSolver::set_probe_dofs(const Eigen::Vector3d& t, Eigen::VectorXd* u) const {
  for (int d = 0; d < num_dofs(); ++d)
    if (probe_dof_component_[d] >= 0) (*u)[d] = probe_base_[d] + t[probe_dof_component_[d]] * unit_;
}

void PathSolver::set_probe_translation(const Eigen::Vector3d& dt, Eigen::VectorXd* v) const {
  for (int d = 0; d < num_dofs(); ++d)
    if (probe_dof_component_[d] >= 0) (*v)[d] = dt[probe_dof_component_[d]] * unit_;
}

double PathSolver::free_norm(const Eigen::VectorXd& v) const {
  double s = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (role_[d] == DofRole::kFree) s += v[d] * v[d];
  return std::sqrt(s);
}

double PathSolver::reaction_norm(const Eigen::VectorXd& f) const {
  double s = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (role_[d] != DofRole::kFree) s += f[d] * f[d];
  return std::sqrt(s);
}

Eigen::Vector3d PathSolver::force_felt() const {
  if (sliding_) return sliding_->force_on_probe(u_, centre_m(t_));
  Eigen::VectorXd scratch;
  const Eigen::VectorXd& f = state_force(&scratch);
  Eigen::Vector3d felt = Eigen::Vector3d::Zero();
  for (int d = 0; d < num_dofs(); ++d)
    if (probe_dof_component_[d] >= 0) felt[probe_dof_component_[d]] -= f[d];
  return felt;
}

const Eigen::VectorXd& PathSolver::state_force(Eigen::VectorXd* scratch) const {
  if (state_force_valid_) return state_force_;
  assembler_->energy_and_force(u_, scratch);
  return *scratch;
}

Eigen::VectorXd PathSolver::probe_reactions() const {
  // Frictionless: the resultant force of the sphere on the body.
  if (sliding_) return -force_felt();
  Eigen::VectorXd scratch;
  const Eigen::VectorXd& f = state_force(&scratch);
  int count = 0;
  for (int d = 0; d < num_dofs(); ++d) count += probe_dof_component_[d] >= 0 ? 1 : 0;
  Eigen::VectorXd h(count);
  int k = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (probe_dof_component_[d] >= 0) h[k++] = f[d];
  return h;
}

void PathSolver::assemble(const Eigen::VectorXd& u, bool project_psd, double* energy) {
  const auto start = Clock::now();
  *energy = assembler_->energy_force_tangent(u, &f_, &k_values_, project_psd);
  if (sliding_ && std::isfinite(*energy)) {
    *energy += sliding_->add_force(u, centre_m(t_solve_), &f_);
    sliding_->add_tangent(u, centre_m(t_solve_), &k_values_, project_psd);
  }
  timings_.assembly += seconds_since(start);
  ++timings_.assemblies;
}

// Replaces constrained rows and columns by identity; the pattern stays the same.
void PathSolver::constrain_values() {
  const SymmetricPattern& p = assembler_->pattern();
  for (int col = 0; col < p.n; ++col) {
    const bool col_free = role_[col] == DofRole::kFree;
    for (int k = p.col_ptr[col]; k < p.col_ptr[col + 1]; ++k) {
      const int row = p.row_idx[k];
      if (col_free && role_[row] == DofRole::kFree) continue;
      k_values_[k] = row == col ? 1.0 : 0.0;
    }
  }
}

// Factorises the constrained tangent held in k_values_; if it is not positive definite,
// re-assembles with element stiffnesses projected to PSD (a descent direction) and retries.
bool PathSolver::factorize_with_fallback(const Eigen::VectorXd& u, SparseCholesky* target) {
  factor_ = target;
  constrain_values();
  auto start = Clock::now();
  bool ok = target->factorize(k_values_);
  timings_.factorize += seconds_since(start);
  ++timings_.factorizations;
  if (ok) return true;
  ++timings_.psd_fallbacks;
  double energy = 0;
  Eigen::VectorXd f_keep = f_;
  assemble(u, /*project_psd=*/true, &energy);
  f_ = f_keep;
  constrain_values();
  // A projected tangent can be singular (zero-energy modes); a tiny diagonal shift keeps it SPD.
  const SymmetricPattern& p = assembler_->pattern();
  double max_diag = 0;
  for (int c = 0; c < p.n; ++c) max_diag = std::max(max_diag, std::abs(k_values_[p.diag[c]]));
  for (int c = 0; c < p.n; ++c)
    if (role_[c] == DofRole::kFree) k_values_[p.diag[c]] += 1e-10 * max_diag;
  start = Clock::now();
  ok = target->factorize(k_values_);
  timings_.factorize += seconds_since(start);
  ++timings_.factorizations;
  return ok;
}

// Newton iterations at the current probe position until ||r_free|| <= abs + rel * ||reactions||.
// Full Newton refactorises every iteration. Inexact Newton (inexact_newton()) keeps the factor
// it has (the predictor's, or its own last) as a preconditioner: each iteration assembles the
// tangent at the current iterate and solves with it by preconditioned conjugate gradients; it
// refactorises at the current iterate only when CG does not converge (preconditioned_cg()) or
// its direction finds no decrease.
bool PathSolver::newton(double rel_tol, MoveResult* result, bool have_factor) {
  result->residual_history.clear();
  const bool inexact = inexact_newton();
  have_factor = have_factor && inexact;
  bool factor_current = false;   // the factor is of the current iterate
  bool tangent_current = false;  // k_values_ is the tangent at the current iterate
  bool force_current = false;    // inexact: f_ and energy are the accepted trial's
  double energy = 0;
  auto free_residual = [&] {
    r_ = f_;
    for (int d = 0; d < num_dofs(); ++d)
      if (role_[d] != DofRole::kFree) r_[d] = 0.0;
  };
  for (int it = 0;; ++it) {
    if (!force_current) {
      assemble(u_, false, &energy);
      tangent_current = true;
    }
    if (!std::isfinite(energy)) {
      result->failure = SolveFailure::kInverted;
      result->reason = "an element is inverted at the start of the Newton solve";
      return false;
    }
    free_residual();
    const double rnorm = r_.norm();
    result->residual = rnorm;
    result->residual_history.push_back(rnorm);
    if (!std::isfinite(rnorm)) {
      result->failure = SolveFailure::kNotFinite;
      result->reason = "residual is not finite";
      return false;
    }
    if (rnorm <= options_.absolute_tolerance + rel_tol * reaction_norm(f_)) return true;
    const bool progressing =
        it >= kProgressWindow && it < kMaxIterationFactor * options_.max_iterations &&
        rnorm < kProgressFactor * result->residual_history[it - kProgressWindow];
    if (it >= options_.max_iterations && !progressing) {
      result->failure = SolveFailure::kMaxIterations;
      result->reason =
          "Newton reached " + std::to_string(it) + " iterations with residual " + sci(rnorm) + " N";
      return false;
    }
    if (!tangent_current) {
      assemble(u_, false, &energy);
      tangent_current = true;
      free_residual();
    }
    double e_trial = 0;
    for (;;) {
      ++result->iterations;  // a linear solve (a retry after a preconditioned one is another)
      bool solved = false;
      if (inexact && have_factor && !factor_current) {
        constrain_values();
        CgOutcome cg = preconditioned_cg();
        if (cg == CgOutcome::kNegativeCurvature) {
          // An indefinite tangent: CG with the PSD-projected one (what full Newton would
          // factorise).
          ++timings_.psd_fallbacks;
          assemble(u_, /*project_psd=*/true, &energy);
          constrain_values();
          cg = preconditioned_cg();
        }
        solved = cg == CgOutcome::kConverged;
      }
      if (!solved) {
        if (!factorize_with_fallback(u_, cholesky_.get())) {
          result->failure = SolveFailure::kNotFinite;
          result->reason = "tangent factorisation failed even after PSD projection";
          return false;
        }
        have_factor = factor_current = true;
        const auto start = Clock::now();
        factor_->solve(-r_, &du_);
        timings_.solve += seconds_since(start);
      }
      if (!du_.allFinite()) {
        result->failure = SolveFailure::kNotFinite;
        result->reason = "Newton direction is not finite";
        return false;
      }
      // Backtracking line search on the potential energy; in the round-off regime near the
      // solution energy differences are meaningless, so a residual decrease is accepted too.
      const double slope = r_.dot(du_);
      double alpha = 1.0;
      bool accepted = false;
      bool any_finite = false;
      for (int ls = 0; ls < kMaxLineSearch; ++ls, alpha *= 0.5) {
        trial_ = u_ + alpha * du_;
        e_trial = total_energy_and_force(trial_, &f_trial_);
        if (!std::isfinite(e_trial)) continue;
        any_finite = true;
        if (e_trial <= energy + kArmijo * alpha * slope) {
          accepted = true;
          break;
        }
        if (free_norm(f_trial_) < (1.0 - kArmijo * alpha) * rnorm) {
          accepted = true;
          break;
        }
      }
      if (accepted) break;
      if (inexact && !factor_current) {  // a preconditioned direction: retry with a new factor
        have_factor = false;
        continue;
      }
      result->failure = any_finite ? SolveFailure::kLineSearch : SolveFailure::kInverted;
      result->reason = any_finite ? "line search found no decrease along the Newton direction"
                                  : "every line-search trial inverted an element";
      return false;
    }
    factor_current = tangent_current = false;
    u_ = trial_;
    if (inexact) {  // the line search already evaluated the new iterate
      std::swap(f_, f_trial_);
      energy = e_trial;
      force_current = true;
    }
  }
}

// Solves K du_ = -r_ (K: the constrained tangent in k_values_) by conjugate gradients
// preconditioned with factor_ (a factorisation of a nearby tangent), to a relative residual of
// kInexactTolerance. kNotConverged if that takes more than kMaxInnerIterations (the caller then
// factorises the tangent itself); kNegativeCurvature if CG meets a direction of non-positive
// curvature (the caller retries with the PSD-projected tangent).
PathSolver::CgOutcome PathSolver::preconditioned_cg() {
  const auto start = Clock::now();
  const SymmetricPattern& pattern = assembler_->pattern();
  du_.setZero(num_dofs());
  cg_r_ = -r_;
  const double target = kInexactTolerance * cg_r_.norm();
  factor_->solve(cg_r_, &cg_z_);
  cg_p_ = cg_z_;
  double rz = cg_r_.dot(cg_z_);
  CgOutcome outcome = CgOutcome::kNotConverged;
  for (int k = 0; k < kMaxInnerIterations; ++k) {
    symmetric_multiply(pattern, k_values_, cg_p_, &cg_q_);
    const double curvature = cg_p_.dot(cg_q_);
    if (!(curvature > 0)) {
      outcome = CgOutcome::kNegativeCurvature;
      break;
    }
    const double step = rz / curvature;
    du_ += step * cg_p_;
    cg_r_ -= step * cg_q_;
    ++timings_.inner_iterations;
    if (cg_r_.norm() <= target) {
      outcome = CgOutcome::kConverged;
      break;
    }
    factor_->solve(cg_r_, &cg_z_);
    const double rz_next = cg_r_.dot(cg_z_);
    cg_p_ = cg_z_ + (rz_next / rz) * cg_p_;
    rz = rz_next;
  }
  timings_.solve += seconds_since(start);
  return outcome;
}

// The predictor at (u_, t_from) for the probe step dt (DOF vector): f_, K dt with the
// unconstrained tangent, and factor_ its factorisation. A move's first sub-step under inexact
// Newton keeps the factor (in source_cholesky_, with f and K): the next move from the same state
// (bitwise) reuses them without assembling or factorising.
bool PathSolver::predictor_factor(const Eigen::Vector3d& t_from, const Eigen::VectorXd& dt,
                                  bool move_start, Eigen::VectorXd* k_dt, MoveResult* result) {
  const bool keep = inexact_newton() && move_start;
  if (keep && source_valid_ && t_from == source_t_ && u_.size() == source_u_.size() &&
      (u_.array() == source_u_.array()).all() &&
      (!sliding_ || sliding_->multipliers() == source_multipliers_)) {
    f_ = source_f_;
    symmetric_multiply(assembler_->pattern(), source_k_, dt, k_dt);
    factor_ = source_cholesky_.get();
    return true;
  }
  double energy = 0;
  assemble(u_, false, &energy);
  if (!std::isfinite(energy)) {
    result->failure = SolveFailure::kInverted;
    result->reason = "start state has an inverted element";
    return false;
  }
  if (keep) {
    if (!source_cholesky_) {
      source_cholesky_ = std::make_unique<SparseCholesky>(assembler_->pattern());
      timings_.analyze += source_cholesky_->analyze_seconds();
    }
    source_valid_ = false;
    source_u_ = u_;
    source_t_ = t_from;
    source_f_ = f_;
    source_k_ = k_values_;
    if (sliding_) source_multipliers_ = sliding_->multipliers();
  }
  symmetric_multiply(assembler_->pattern(), k_values_, dt, k_dt);
  const long long before = timings_.factorizations;
  const bool ok = factorize_with_fallback(u_, keep ? source_cholesky_.get() : cholesky_.get());
  if (keep) result->start_factorisations += static_cast<int>(timings_.factorizations - before);
  if (!ok) {
    result->failure = SolveFailure::kNotFinite;
    result->reason = "tangent factorisation failed in the predictor";
    return false;
  }
  source_valid_ = keep;
  return true;
}

// One sub-step: tangent predictor from t_from to t_to, then Newton corrections.
bool PathSolver::substep(const Eigen::Vector3d& t_from, const Eigen::Vector3d& t_to, double rel_tol,
                         bool move_start, MoveResult* result) {
  // Sticking contact: decisions on reactions need converged reactions at every sub-step.
  if (contact_) rel_tol = options_.tolerance;
  if (sliding_) sliding_->set_penalty_scale(1.0);
  const bool last = rel_tol <= options_.tolerance;
  // Frictionless contact with the body at rest and nothing within reach: nothing to solve.
  if (sliding_ && u_.isZero(0.0)) {
    sliding_->reset_multipliers();
    if (!sliding_->any_active(u_, centre_m(t_to))) return true;
  }
  t_solve_ = t_from;
  // Contact with nothing touched and the body at rest: only collision detection is needed.
  if (contact_ && contact_->touched().empty() && u_.isZero(0.0))
    return settle_contact(t_to, rel_tol, result);
  // Predictor: K_FF du_F = -r_F - K_FP dt.
  Eigen::VectorXd dt = Eigen::VectorXd::Zero(num_dofs());
  set_probe_translation(t_to - t_from, &dt);
  Eigen::VectorXd k_dt;
  if (!predictor_factor(t_from, dt, move_start, &k_dt, result)) return false;
  if (sliding_) {
    // The sphere's move loads the surface through d2Psi/du dc.
    Eigen::Matrix<double, Eigen::Dynamic, 3> k_uc = Eigen::MatrixX3d::Zero(num_dofs(), 3);
    Eigen::Matrix3d k_cc = Eigen::Matrix3d::Zero();
    sliding_->add_coupling(u_, centre_m(t_from), &k_uc, &k_cc);
    k_dt += k_uc * ((t_to - t_from) * unit_);
  }
  Eigen::VectorXd rhs = -(f_ + k_dt);
  for (int d = 0; d < num_dofs(); ++d)
    if (role_[d] != DofRole::kFree) rhs[d] = 0.0;
  ++result->iterations;
  auto start = Clock::now();
  factor_->solve(rhs, &du_);
  timings_.solve += seconds_since(start);
  // Take the predictor, shortened if it inverts an element.
  Eigen::VectorXd base = u_;
  set_probe_dofs(t_to, &base);
  double scale = 1.0;
  for (int tries = 0; tries < 8; ++tries, scale *= 0.5) {
    trial_ = base + scale * du_;
    if (std::isfinite(assembler_->energy(trial_))) break;
  }
  if (!std::isfinite(assembler_->energy(trial_))) {
    trial_ = base;
    if (!std::isfinite(assembler_->energy(trial_))) {
      result->failure = SolveFailure::kInverted;
      result->reason = "the probe step inverts an element";
      return false;
    }
  }
  u_ = trial_;
  t_solve_ = t_to;
  if (!newton(rel_tol, result, /*have_factor=*/true)) return false;
  if (sliding_) return settle_sliding(rel_tol, last, result);
  return !contact_ || settle_contact(t_to, rel_tol, result);
}

MoveResult PathSolver::move_to(const Eigen::Vector3d& t_target) {
  const auto start = Clock::now();
  MoveResult result;
  const Eigen::VectorXd u_start = u_;
  const Eigen::Vector3d t_start = t_;
  const ContactSet::Held held_start = contact_ ? contact_->held() : ContactSet::Held{};
  const std::vector<double> multipliers_start =
      sliding_ ? sliding_->multipliers() : std::vector<double>{};
  auto restore_contact = [&](const ContactSet::Held& h) {
    if (!contact_) return;
    contact_->restore(h);
    apply_contact_roles();
  };
  const long long factorisations_start = timings_.factorizations;
  state_force_valid_ = false;
  // kFast (grab, frictionless contact): one sub-step for the whole move (contact: at most
  // kMaxStepPerRadius), halved only where it fails.
  double nominal = inexact_newton() ? 1.0 : 1.0 / options_.substeps;
  if (sliding_) {
    const double length = (t_target - t_start).norm() * unit_;
    const double most = kMaxStepPerRadius * sliding_->radius();
    if (length * nominal > most) nominal = 1.0 / std::ceil(length / most);
  }
  // The fast algorithm halves from the whole move down to at least the reference algorithm's
  // smallest sub-step (max_cutbacks halvings of 1 / substeps): its ladder of powers of 1/2
  // reaches that size or goes below it.
  const double reference_smallest = 1.0 / options_.substeps / std::pow(2.0, options_.max_cutbacks);
  const double smallest = nominal < 1.0 || !inexact_newton()
                              ? nominal / std::pow(2.0, options_.max_cutbacks)
                              : std::pow(2.0, std::floor(std::log2(reference_smallest) + 1e-9));
  double s = 0, ds = nominal;
  int streak = 0;
  while (s < 1.0) {
    const double s_next = s + ds > 1.0 - 1e-12 ? 1.0 : s + ds;
    const Eigen::Vector3d t_from = t_start + s * (t_target - t_start);
    const Eigen::Vector3d t_to = t_start + s_next * (t_target - t_start);
    const Eigen::VectorXd u_saved = u_;
    const ContactSet::Held held_saved = contact_ ? contact_->held() : ContactSet::Held{};
    const std::vector<double> multipliers_saved =
        sliding_ ? sliding_->multipliers() : std::vector<double>{};
    const double tol =
        s_next == 1.0 ? options_.tolerance : std::max(options_.tolerance, kIntermediateRelTol);
    if (substep(t_from, t_to, tol, s == 0, &result)) {
      s = s_next;
      t_ = t_to;
      ++result.substeps;
      if (++streak >= 2 && ds < nominal) {
        ds = std::min(nominal, 2 * ds);
        streak = 0;
      }
      continue;
    }
    u_ = u_saved;
    restore_contact(held_saved);
    if (sliding_) sliding_->set_multipliers(multipliers_saved);
    streak = 0;
    ds *= 0.5;
    ++result.cutbacks;
    if (ds < smallest * (1 - 1e-9)) {
      result.ok = false;
      const std::string last = result.reason;
      if (result.failure == SolveFailure::kNone) result.failure = SolveFailure::kCutbackLimit;
      result.reason = "sub-step cut back " + std::to_string(result.cutbacks) +
                      " times and still failing at " + std::to_string(s * 100) +
                      "% of the move; last: " + last;
      result.factorisations = static_cast<int>(timings_.factorizations - factorisations_start);
      u_ = u_start;
      t_ = t_start;
      t_solve_ = t_start;
      restore_contact(held_start);
      if (sliding_) sliding_->set_multipliers(multipliers_start);
      result.wall_ms = 1e3 * seconds_since(start);
      return result;
    }
  }
  result.ok = true;
  result.failure = SolveFailure::kNone;
  result.reason.clear();
  if (!contact_ && !sliding_ && result.substeps > 0) {  // f_ is the converged Newton's force
    state_force_ = f_;
    state_force_valid_ = true;
  }
  result.factorisations = static_cast<int>(timings_.factorizations - factorisations_start);
  result.wall_ms = 1e3 * seconds_since(start);
  return result;
}

Eigen::Matrix3d PathSolver::haptic_stiffness(Eigen::MatrixX3d* du_dp) {
  if (sliding_) return sliding_stiffness(du_dp);
  if (du_dp) du_dp->setZero(num_dofs(), 3);
  double energy = 0;
  assemble(u_, false, &energy);
  const std::vector<double> k_full = k_values_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> y(num_dofs(), 3);
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(num_dofs());
    for (int d = 0; d < num_dofs(); ++d)
      if (probe_dof_component_[d] == c) e[d] = 1.0;
    Eigen::VectorXd col;
    symmetric_multiply(assembler_->pattern(), k_full, e, &col);
    y.col(c) = col;
  }
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  if (!factorize_with_fallback(u_, cholesky_.get()))
    return stiffness * std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix<double, Eigen::Dynamic, 3> y_free = y;
  for (int d = 0; d < num_dofs(); ++d)
    if (role_[d] != DofRole::kFree) y_free.row(d).setZero();
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd z;
    cholesky_->solve(y_free.col(c), &z);
    // du/dp_c: the probe DOFs of component c move with the probe, the free ones by -K_FF^-1 K_FP.
    if (du_dp)
      for (int d = 0; d < num_dofs(); ++d)
        (*du_dp)(d, c) = role_[d] == DofRole::kFree     ? -z[d]
                         : probe_dof_component_[d] == c ? 1.0
                                                        : 0.0;
    for (int c2 = 0; c2 < 3; ++c2) {
      double kpp = 0;
      for (int d = 0; d < num_dofs(); ++d)
        if (probe_dof_component_[d] == c2) kpp += y(d, c);
      // d(felt_c2)/d(t_c) = -(K_PP - K_PF K_FF^-1 K_FP)_{c2,c}; per metre -> per mesh unit.
      stiffness(c2, c) = -(kpp - y_free.col(c2).dot(z)) * unit_;
    }
  }
  return stiffness;
}

}  // namespace hapstate

namespace hapstate {

// Frictionless contact: F = -dPsi/dc at the equilibrium u*(c), so
// dF/dc = -(Psi_cc - Psi_cu K^-1 Psi_uc) with K the full tangent on the free DOFs; the active
// gaps are held as the constraints they converge to (a stiff penalty in the Hessian).
Eigen::Matrix3d PathSolver::sliding_stiffness(Eigen::MatrixX3d* du_dp) {
  if (du_dp) du_dp->setZero(num_dofs(), 3);
  t_solve_ = t_;
  const Eigen::Vector3d centre = centre_m(t_);
  const double stiff = kStiffnessPenaltyFactor * sliding_->base_penalty();
  assembler_->energy_force_tangent(u_, &f_, &k_values_);
  sliding_->add_tangent(u_, centre, &k_values_, false, stiff);
  Eigen::Matrix<double, Eigen::Dynamic, 3> k_uc = Eigen::MatrixX3d::Zero(num_dofs(), 3);
  Eigen::Matrix3d k_cc = Eigen::Matrix3d::Zero();
  sliding_->add_coupling(u_, centre, &k_uc, &k_cc, stiff);
  for (int d = 0; d < num_dofs(); ++d)
    if (role_[d] != DofRole::kFree) k_uc.row(d).setZero();
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  if (k_cc.isZero(0.0)) return stiffness;
  if (!factorize_with_fallback(u_, cholesky_.get()))
    return stiffness * std::numeric_limits<double>::quiet_NaN();
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd z;
    cholesky_->solve(k_uc.col(c), &z);
    if (du_dp)  // du/dc = -K^-1 K_uc on the free DOFs
      for (int d = 0; d < num_dofs(); ++d)
        (*du_dp)(d, c) = role_[d] == DofRole::kFree ? -z[d] : 0.0;
    for (int c2 = 0; c2 < 3; ++c2)
      stiffness(c2, c) = -(k_cc(c2, c) - k_uc.col(c2).dot(z)) * unit_;  // per mesh unit
  }
  return stiffness;
}

}  // namespace hapstate
