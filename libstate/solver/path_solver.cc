#include "solver/path_solver.h"

#include "util/elapsed.h"
#include "util/error.h"
#include "util/text.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace hapstate {
namespace {

using Clock = std::chrono::steady_clock;

// Intermediate sub-steps only need to stay close to the equilibrium path; the final
// sub-step is solved to the user's tolerance.
constexpr double kIntermediateRelTol = 1e-2;
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
      unit_(problem.unit),
      num_nodes_(problem.mesh.num_nodes()),
      options_(problem.solver) {
  const Eigen::Matrix3Xd positions_m = problem.mesh.nodes * unit_;
  assembler_ = std::make_unique<Assembler>(positions_m, problem.mesh.tets, *material_);
  loads_ = problem.loads;
  assembler_->set_loads(&loads_);
  cholesky_ = std::make_unique<SparseCholesky>(assembler_->pattern());
  factor_ = cholesky_.get();
  timings_.analyze = cholesky_->analyze_seconds();
  timings_.factor_bytes = cholesky_->factor_bytes();
  timings_.single_factor_bytes = cholesky_->factor_bytes(/*single=*/true);
  scene_.role = problem.constraints.role;
  // Nodes used by no tet have no stiffness: hold them where they are.
  std::vector<bool> used(num_nodes_, false);
  for (int e = 0; e < problem.mesh.num_tets(); ++e)
    for (int a = 0; a < 4; ++a) used[problem.mesh.tets(a, e)] = true;
  for (int n = 0; n < num_nodes_; ++n)
    if (!used[n])
      for (int c = 0; c < 3; ++c) scene_.role[3 * n + c] = DofRole::kFixed;
  scene_.component.assign(3 * num_nodes_, -1);
  rest_ = problem.rest_m.size() == num_dofs() ? problem.rest_m : Eigen::VectorXd::Zero(num_dofs());
  scene_.base = rest_;  // a grabbed DOF follows the probe from where the rest state put it
  boundary_ = make_probe_boundary(problem, *assembler_, scene_.role);
  reset();
}

PathSolver::~PathSolver() = default;

int PathSolver::num_dofs() const { return assembler_->num_dofs(); }

void PathSolver::reset() {
  u_ = rest_;
  state_force_valid_ = false;
  t_.setZero();
  t_solve_.setZero();
  boundary_->reset();
  apply_prescription();
}

MoveResult PathSolver::settle_under_loads() {
  constexpr double kFirstStep = 0.25, kSmallestStep = 1.0 / 4096;
  constexpr int kEasyIterations = 8;  // a step that took at most this many: the next one doubles
  const auto start = Clock::now();
  MoveResult result;
  const long long factorisations_before = timings_.factorisations;
  state_force_valid_ = false;
  double scale = 0, step = kFirstStep;
  Eigen::VectorXd converged = u_;
  while (scale < 1.0) {
    const double next = std::min(1.0, scale + step);
    assembler_->set_load_scale(next);
    MoveResult attempt;
    const bool ok = newton(options_.tolerance, &attempt, /*have_factor=*/false);
    result.iterations += attempt.iterations;
    result.residual = attempt.residual;
    if (ok) {
      scale = next;
      converged = u_;
      ++result.substeps;
      if (attempt.iterations <= kEasyIterations) step = std::min(1.0, 2 * step);
      continue;
    }
    u_ = converged;
    ++result.cutbacks;
    step /= 2;
    if (step < kSmallestStep) {
      assembler_->set_load_scale(scale);
      result.ok = false;
      result.failure = attempt.failure;
      char where[96];
      std::snprintf(where, sizeof where,
                    "the body loads could not be raised past %.4g of their value: ", scale);
      result.reason = where + attempt.reason;
      break;
    }
  }
  result.factorisations = static_cast<int>(timings_.factorisations - factorisations_before);
  result.wall_ms = 1e3 * seconds_since(start);
  return result;
}

void PathSolver::set_state(const Eigen::VectorXd& u_m, const Eigen::Vector3d& t,
                           const std::vector<int>& touched,
                           const std::vector<double>& multipliers) {
  boundary_->set_state(u_m, t, touched, multipliers);
  u_ = u_m;
  t_ = t;
  t_solve_ = t;
  state_force_valid_ = false;
  apply_prescription();
}

void PathSolver::apply_prescription() {
  now_ = scene_;
  boundary_->prescribe(&now_);
}

double PathSolver::total_energy_and_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const {
  double e = assembler_->energy_and_force(u, f);
  if (std::isfinite(e)) e += boundary_->add_force(u, t_solve_, f);
  return e;
}

// The solver as the boundary's settling loop sees it.
class PathSolver::Host final : public SettleHost {
 public:
  explicit Host(PathSolver* solver) : s_(solver) {}
  Eigen::VectorXd& state() override { return s_->u_; }
  const Eigen::VectorXd& force() const override { return s_->f_; }
  void prescription_changed(const Eigen::Vector3d& t) override {
    s_->apply_prescription();
    s_->set_probe_dofs(t, &s_->u_);
  }
  bool newton(double rel_tol, MoveResult* result, bool have_factor) override {
    return s_->newton(rel_tol, result, have_factor);
  }

 private:
  PathSolver* s_;
};

Eigen::Matrix3Xd PathSolver::displacements() const {
  return Eigen::Map<const Eigen::Matrix3Xd>(u_.data(), 3, num_nodes_) / unit_;
}

void PathSolver::set_probe_dofs(const Eigen::Vector3d& t, Eigen::VectorXd* u) const {
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.component[d] >= 0) (*u)[d] = now_.base[d] + t[now_.component[d]] * unit_;
}

void PathSolver::set_probe_translation(const Eigen::Vector3d& dt, Eigen::VectorXd* v) const {
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.component[d] >= 0) (*v)[d] = dt[now_.component[d]] * unit_;
}

double PathSolver::longest_node_step(const Eigen::VectorXd& du) const {
  double longest = 0;
  for (int n = 0; n < num_nodes_; ++n) longest = std::max(longest, du.segment<3>(3 * n).norm());
  return longest;
}

double PathSolver::free_norm(const Eigen::VectorXd& v) const {
  double s = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.role[d] == DofRole::kFree) s += v[d] * v[d];
  return std::sqrt(s);
}

double PathSolver::reaction_norm(const Eigen::VectorXd& f) const {
  double s = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.role[d] != DofRole::kFree) s += f[d] * f[d];
  return std::sqrt(s);
}

Eigen::Vector3d PathSolver::force_felt() const {
  if (boundary_->force_from_energy()) return boundary_->force_on_probe(u_, t_);
  Eigen::VectorXd scratch;
  const Eigen::VectorXd& f = state_force(&scratch);
  Eigen::Vector3d felt = Eigen::Vector3d::Zero();
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.component[d] >= 0) felt[now_.component[d]] -= f[d];
  return felt;
}

const Eigen::VectorXd& PathSolver::state_force(Eigen::VectorXd* scratch) const {
  if (state_force_valid_) return state_force_;
  assembler_->energy_and_force(u_, scratch);
  return *scratch;
}

Eigen::VectorXd PathSolver::probe_reactions() const {
  // Frictionless: the resultant force of the sphere on the body.
  if (boundary_->force_from_energy()) return -force_felt();
  Eigen::VectorXd scratch;
  const Eigen::VectorXd& f = state_force(&scratch);
  int count = 0;
  for (int d = 0; d < num_dofs(); ++d) count += now_.component[d] >= 0 ? 1 : 0;
  Eigen::VectorXd h(count);
  int k = 0;
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.component[d] >= 0) h[k++] = f[d];
  return h;
}

PathSolver::StartFactor* PathSolver::kept_start_factor(const Eigen::Vector3d& t) {
  for (StartFactor& slot : start_factors_)
    if (slot.valid && t == slot.t && u_.size() == slot.u.size() &&
        (u_.array() == slot.u.array()).all() && boundary_->save() == slot.boundary)
      return &slot;
  return nullptr;
}

PathSolver::StartFactor& PathSolver::start_factor_to_fill(const Eigen::Vector3d& t) {
  StartFactor* slot = &start_factors_[0];
  for (StartFactor& s : start_factors_)
    if (!s.valid || (slot->valid && s.last_use < slot->last_use)) slot = &s;
  if (!slot->cholesky) {
    slot->cholesky = std::make_unique<SparseCholesky>(assembler_->pattern());
    timings_.analyze += slot->cholesky->analyze_seconds();
  }
  slot->valid = false;
  slot->u = u_;
  slot->t = t;
  slot->f = f_;
  slot->k = k_values_;
  slot->boundary = boundary_->save();
  return *slot;
}

// The predictor at (u_, t_from) for the probe step dt (DOF vector): f_, K dt with the
// unconstrained tangent, and factor_ its factorisation. A move's first sub-step under inexact
// Newton keeps the factor (with f and K) in one of start_factors_: the next move from the same
// state (bitwise) reuses them without assembling or factorising. Two are kept, the least
// recently used replaced: a direction that records a midpoint starts its second half there, and
// with one slot that start evicted the source's factor, which the source's next direction then
// factorised again (measured: docs/benchmarks.md, "The solver's constants").
bool PathSolver::predictor_factor(const Eigen::Vector3d& t_from, const Eigen::VectorXd& dt,
                                  bool move_start, Eigen::VectorXd* k_dt, MoveResult* result) {
  const bool keep = inexact_newton() && move_start;
  if (keep) {
    if (StartFactor* slot = kept_start_factor(t_from)) {
      f_ = slot->f;
      symmetric_multiply(assembler_->pattern(), slot->k, dt, k_dt);
      factor_ = slot->cholesky.get();
      slot->last_use = ++start_factor_uses_;
      return true;
    }
  }
  double energy = 0;
  assemble(u_, false, &energy);
  if (!std::isfinite(energy)) {
    result->failure = SolveFailure::kInverted;
    result->reason = "start state has an inverted element";
    return false;
  }
  StartFactor* slot = keep ? &start_factor_to_fill(t_from) : nullptr;
  symmetric_multiply(assembler_->pattern(), k_values_, dt, k_dt);
  const long long before = timings_.factorisations;
  const bool ok = factorize_with_fallback(u_, keep ? slot->cholesky.get() : cholesky_.get());
  if (keep) result->start_factorisations += static_cast<int>(timings_.factorisations - before);
  if (!ok) {
    result->failure = SolveFailure::kNotFinite;
    result->reason = "tangent factorisation failed in the predictor";
    return false;
  }
  if (keep) {
    slot->valid = true;
    slot->last_use = ++start_factor_uses_;
  }
  return true;
}

// One sub-step: tangent predictor from t_from to t_to, then Newton corrections.
bool PathSolver::substep(const Eigen::Vector3d& t_from, const Eigen::Vector3d& t_to, double rel_tol,
                         bool move_start, MoveResult* result) {
  if (boundary_->converges_every_substep()) rel_tol = options_.tolerance;
  const bool last = rel_tol <= options_.tolerance;
  t_solve_ = t_from;
  Host host(this);
  bool settled = false;
  if (boundary_->settled_without_solve(host, t_to, options_, result, &settled)) return settled;
  // Predictor: K_FF du_F = -r_F - K_FP dt.
  Eigen::VectorXd dt = Eigen::VectorXd::Zero(num_dofs());
  set_probe_translation(t_to - t_from, &dt);
  Eigen::VectorXd k_dt;
  if (!predictor_factor(t_from, dt, move_start, &k_dt, result)) return false;
  boundary_->add_predictor_load(u_, t_from, (t_to - t_from) * unit_, &k_dt);
  Eigen::VectorXd rhs = -(f_ + k_dt);
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.role[d] != DofRole::kFree) rhs[d] = 0.0;
  ++result->iterations;
  auto start = Clock::now();
  back_substitute(*factor_, rhs, &du_);
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
  if (!newton(boundary_->first_solve_tolerance(rel_tol, last), result, /*have_factor=*/true))
    return false;
  return boundary_->settle(host, t_to, rel_tol, last, options_, result);
}

// What a failed fallback puts back: the state at the start of a move.
struct PathSolver::StartState {
  Eigen::VectorXd u;
  Eigen::Vector3d t;
  BoundaryState boundary;
};

PathSolver::StartState PathSolver::start_state() const { return {u_, t_, boundary_->save()}; }

void PathSolver::restore(const StartState& start) {
  u_ = start.u;
  t_ = start.t;
  t_solve_ = start.t;
  state_force_valid_ = false;
  boundary_->restore(start.boundary);
  apply_prescription();
}

// A move whose sub-steps fail even when cut back is tried again as kMoveSplits[i] equal moves.
// Each piece ends converged to the full tolerance, where one move's intermediate sub-steps are
// solved only to kIntermediateRelTol and its cut-backs restart from such a loosely converged
// state: near a limit point (StVK in compression) that is the difference between converging
// and not (the numerical stress suite's cases).
constexpr int kMoveSplits[] = {4, 16};

MoveResult PathSolver::move_to(const Eigen::Vector3d& t_target) {
  MoveResult result = move_once(t_target);
  if (result.ok) return result;
  const StartState start = start_state();
  const Eigen::Vector3d t_start = t_;
  std::string reasons = result.reason;
  for (const int pieces : kMoveSplits) {
    MoveResult piece;
    int k = 1;
    for (; k <= pieces; ++k) {
      piece = move_once(t_start + (t_target - t_start) * (static_cast<double>(k) / pieces));
      result.substeps += piece.substeps;
      result.cutbacks += piece.cutbacks;
      result.iterations += piece.iterations;
      result.factorisations += piece.factorisations;
      result.start_factorisations += piece.start_factorisations;
      result.active_set_iterations += piece.active_set_iterations;
      result.wall_ms += piece.wall_ms;
      if (!piece.ok) break;
    }
    result.residual = piece.residual;
    result.residual_history = std::move(piece.residual_history);
    if (piece.ok) {
      result.ok = true;
      result.failure = SolveFailure::kNone;
      result.reason.clear();
      result.split_pieces = pieces;
      return result;
    }
    result.failure = piece.failure;
    reasons += "; split into " + std::to_string(pieces) + " moves, move " + std::to_string(k) +
               " failed: " + piece.reason;
    restore(start);
  }
  result.reason = reasons;
  return result;
}

MoveResult PathSolver::move_once(const Eigen::Vector3d& t_target) {
  const auto start = Clock::now();
  MoveResult result;
  const StartState at_start = start_state();
  const Eigen::Vector3d t_start = t_;
  const long long factorisations_start = timings_.factorisations;
  state_force_valid_ = false;
  // kFast (grab, frictionless contact): one sub-step for the whole move (at most the boundary's
  // longest_step_m), halved only where it fails.
  double nominal = inexact_newton() ? 1.0 : 1.0 / options_.substeps;
  const double length = (t_target - t_start).norm() * unit_;
  const double most = boundary_->longest_step_m();
  if (length * nominal > most) nominal = 1.0 / std::ceil(length / most);
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
    const StartState saved = start_state();
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
    restore(saved);
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
      result.factorisations = static_cast<int>(timings_.factorisations - factorisations_start);
      restore(at_start);
      result.wall_ms = 1e3 * seconds_since(start);
      return result;
    }
  }
  result.ok = true;
  result.failure = SolveFailure::kNone;
  result.reason.clear();
  if (boundary_->keeps_newton_force() && result.substeps > 0) {  // the converged Newton's f_
    state_force_ = f_;
    state_force_valid_ = true;
  }
  result.factorisations = static_cast<int>(timings_.factorisations - factorisations_start);
  result.wall_ms = 1e3 * seconds_since(start);
  return result;
}

// F = -dPi*/dc at the equilibrium u*(c), c the probe position. With the tangent K on the free
// DOFs, the coupling K_uc of the free DOFs to c and K_cc:
//   dF/dc = -(K_cc - K_cu K^-1 K_uc),   du/dc = -K^-1 K_uc on the free DOFs.
// Prescribed DOFs (grab, sticking) couple through K's columns: they move with c (du/dc = 1 for
// their component), so K_uc = sum of K's columns of component c and K_cc the sums of K_PP. The
// frictionless sphere couples through its energy (its active gaps held as the constraints they
// converge to).
Eigen::Matrix3d PathSolver::haptic_stiffness(Eigen::MatrixX3d* du_dp, bool keep_factor) {
  if (du_dp) du_dp->setZero(num_dofs(), 3);
  t_solve_ = t_;
  k_elastic_valid_ = false;  // k_values_ below is assembled here
  assembler_->energy_force_tangent(u_, &f_, &k_values_);
  boundary_->add_tangent(u_, t_, &k_values_, false, /*for_stiffness=*/true);
  Eigen::Matrix<double, Eigen::Dynamic, 3> k_uc = Eigen::MatrixX3d::Zero(num_dofs(), 3);
  Eigen::Matrix3d k_cc = Eigen::Matrix3d::Zero();
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(num_dofs());
    for (int d = 0; d < num_dofs(); ++d)
      if (now_.component[d] == c) e[d] = 1.0;
    if (e.isZero(0.0)) continue;
    Eigen::VectorXd col;
    symmetric_multiply(assembler_->pattern(), k_values_, e, &col);
    k_uc.col(c) = col;
    for (int d = 0; d < num_dofs(); ++d)
      if (now_.component[d] >= 0) k_cc(now_.component[d], c) += col[d];
  }
  boundary_->add_coupling(u_, t_, &k_uc, &k_cc, /*for_stiffness=*/true);
  for (int d = 0; d < num_dofs(); ++d)
    if (now_.role[d] != DofRole::kFree) k_uc.row(d).setZero();
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  if (k_cc.isZero(0.0)) return stiffness;  // nothing holds or presses the body
  // keep_factor: the factor is the one the next move's predictor would make here (a probe
  // without an energy of its own adds nothing to this tangent or force), so it is kept as
  // that move's start factor (predictor_factor), the same to the bit.
  StartFactor* slot = keep_factor && inexact_newton() && !boundary_->force_from_energy()
                          ? &start_factor_to_fill(t_)
                          : nullptr;
  SparseCholesky& factor = slot ? *slot->cholesky : *cholesky_;
  if (!factorize_with_fallback(u_, &factor))
    return stiffness * std::numeric_limits<double>::quiet_NaN();
  if (slot) {
    slot->valid = true;
    slot->last_use = ++start_factor_uses_;
  }
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd z;
    back_substitute(factor, k_uc.col(c), &z);
    if (du_dp)
      for (int d = 0; d < num_dofs(); ++d)
        (*du_dp)(d, c) = now_.role[d] == DofRole::kFree ? -z[d]
                         : now_.component[d] == c       ? 1.0
                                                        : 0.0;
    for (int c2 = 0; c2 < 3; ++c2)
      stiffness(c2, c) = -(k_cc(c2, c) - k_uc.col(c2).dot(z)) * unit_;  // per mesh unit
  }
  return stiffness;
}

}  // namespace hapstate
