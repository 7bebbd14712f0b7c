// PathSolver's Newton solve (the paper's inner loop): assembly, the constrained tangent and its
// factorisation (with the PSD fallback), the back-substitutions, Newton with its line search and
// the inexact variant (conjugate gradients preconditioned by a kept factorisation). The moves
// that call it (predictor, sub-steps, cut-backs, splits) are in path_solver.cc.
#include "solver/path_solver.h"

#include "util/elapsed.h"
#include "util/error.h"
#include "util/text.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hapstate {
namespace {

using Clock = std::chrono::steady_clock;

// Inexact Newton (SolverAlgorithm::kFast): conjugate gradients preconditioned by a kept
// factorisation solve each Newton system to this relative residual, in at most this many
// iterations, else the tangent is factorised afresh. 40, between the two best measured, keeps
// the factorisations low on the larger meshes, where one costs most (the measurements behind
// this and the other constants here: docs/benchmarks.md, "The solver's constants").
constexpr double kInexactTolerance = 1e-2;
constexpr int kMaxInnerIterations = 40;
// Newton goes on past SolverOptions::max_iterations while it still converges steadily: the
// residual at least halved over the last kProgressWindow iterations, up to kMaxIterationFactor x
// max_iterations in all. Nearly incompressible bodies (nu >= 0.499) under large strain converge
// only linearly for a while (an ill-conditioned tangent, CG to 1e-2 with a kept preconditioner,
// PSD-projected tangents where it is indefinite) and need 35-90 iterations; cutting the
// sub-step back does not help when it is the move's last (it must reach the full tolerance
// whatever its size); measured with hapstate-stress (docs/benchmarks.md, "Numerical stress
// suite"). A solve that stalls or diverges still fails at max_iterations.
constexpr int kProgressWindow = 10;
constexpr double kProgressFactor = 0.5;
constexpr int kMaxIterationFactor = 4;
// Armijo sufficient-decrease constant and line-search halvings. An iterate of a frictionless
// contact solve that sits just outside a triangle's contact has a tangent without that
// triangle's penalty; a step along its direction meets the penalty at once, and only a step of
// 10^-4 to 10^-5 of the Newton step decreases the energy (after which the triangle is in the
// tangent and Newton proceeds). 12 halvings made such a sub-step fail and be cut back; 20 do not
// (docs/benchmarks.md, "The solver's constants").
// Inexact Newton with a probe that has its own energy (frictionless contact): while the iterate
// has moved less than this fraction of the boundary's longest node step since the last
// assembly (summed over the accepted steps), a Newton iteration keeps that assembly's elastic
// tangent and adds the probe's tangent at the iterate; the contact term changes abruptly (a
// triangle enters or leaves), the elastic one hardly (the values tried: docs/benchmarks.md,
// "The solver's constants").
constexpr double kElasticDrift = 1e-2;
// The conjugate gradients' preconditioner solves with the factor rounded to float
// (SparseCholesky::solve_single): half the bytes per iteration, a few more iterations; faster
// on liverFine (docs/benchmarks.md, "The solver's constants").
constexpr bool kSinglePrecisionPreconditioner = true;
constexpr double kArmijo = 1e-4;
constexpr int kMaxLineSearch = 20;
}  // namespace

void PathSolver::assemble(const Eigen::VectorXd& u, bool project_psd, double* energy) {
  const auto start = Clock::now();
  *energy = assembler_->energy_force_tangent(u, &f_, &k_values_, project_psd);
  k_elastic_valid_ = false;
  if (std::isfinite(*energy)) {
    *energy += boundary_->add_force(u, t_solve_, &f_);
    if (boundary_->force_from_energy() && !project_psd) {
      k_elastic_ = k_values_;
      k_elastic_valid_ = true;
    }
    boundary_->add_tangent(u, t_solve_, &k_values_, project_psd, /*for_stiffness=*/false);
  }
  timings_.assembly += seconds_since(start);
  ++timings_.assemblies;
}

bool PathSolver::probe_tangent_on_elastic(const Eigen::VectorXd& u, bool psd_only) {
  if (!k_elastic_valid_) return false;
  const auto start = Clock::now();
  k_values_ = k_elastic_;
  boundary_->add_tangent(u, t_solve_, &k_values_, psd_only, /*for_stiffness=*/false);
  timings_.assembly += seconds_since(start);
  return true;
}

// Replaces constrained rows and columns by identity; the pattern stays the same.
void PathSolver::constrain_values() {
  const SymmetricPattern& p = assembler_->pattern();
  for (int col = 0; col < p.n; ++col) {
    const bool col_free = now_.role[col] == DofRole::kFree;
    for (int k = p.col_ptr[col]; k < p.col_ptr[col + 1]; ++k) {
      const int row = p.row_idx[k];
      if (col_free && now_.role[row] == DofRole::kFree) continue;
      k_values_[k] = row == col ? 1.0 : 0.0;
    }
  }
}

void PathSolver::back_substitute(SparseCholesky& factor, const Eigen::VectorXd& b,
                                 Eigen::VectorXd* x, bool single) {
  if (single) {
    factor.solve_single(b, x);
    ++timings_.single_back_substitutions;
  } else {
    factor.solve(b, x);
  }
  ++timings_.back_substitutions;
}

// Factorises the constrained tangent held in k_values_; if it is not positive definite,
// re-assembles with element stiffnesses projected to PSD (a descent direction) and retries.
bool PathSolver::factorize_with_fallback(const Eigen::VectorXd& u, SparseCholesky* target) {
  factor_ = target;
  auto factorize = [&] {
    const auto start = Clock::now();
    const bool ok = target->factorize(k_values_);
    timings_.factorize += seconds_since(start);
    ++timings_.factorisations;
    return ok;
  };
  constrain_values();
  if (factorize()) return true;
  ++timings_.psd_fallbacks;
  // The probe's curvature projected away first (cheap); then every element's.
  if (probe_tangent_on_elastic(u, /*psd_only=*/true)) {
    constrain_values();
    if (factorize()) return true;
  }
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
    if (now_.role[c] == DofRole::kFree) k_values_[p.diag[c]] += 1e-10 * max_diag;
  return factorize();
}

// Newton iterations at the current probe position until
// ||r_free|| <= abs + rel * (||reactions|| + ||body force||).
// Full Newton refactorises every iteration. Inexact Newton (inexact_newton()) keeps the factor
// it has (the predictor's, or its own last) as a preconditioner: each iteration assembles the
// tangent at the current iterate (a probe energy's tangent on a nearby iterate's elastic one:
// kElasticDrift) and solves with it by preconditioned conjugate gradients; it
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
  double drift = 0;  // how far u_ moved since the last assembly [m]: the longest node step
  auto free_residual = [&] {
    r_ = f_;
    for (int d = 0; d < num_dofs(); ++d)
      if (now_.role[d] != DofRole::kFree) r_[d] = 0.0;
  };
  for (int it = 0;; ++it) {
    if (!force_current) {
      assemble(u_, false, &energy);
      drift = 0;
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
    if (rnorm <=
        options_.absolute_tolerance + rel_tol * (reaction_norm(f_) + assembler_->load_norm()))
      return true;
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
      const bool near = inexact && drift <= kElasticDrift * boundary_->longest_step_m();
      if (!near || !probe_tangent_on_elastic(u_, /*psd_only=*/false)) {
        assemble(u_, false, &energy);
        drift = 0;
        free_residual();
      }
      tangent_current = true;
    }
    double e_trial = 0, accepted_step = 0;  // the accepted step's longest node move [m]
    for (;;) {
      ++result->iterations;  // a linear solve (a retry after a preconditioned one is another)
      bool solved = false;
      if (inexact && have_factor && !factor_current) {
        constrain_values();
        CgOutcome cg = preconditioned_cg();
        if (cg == CgOutcome::kNegativeCurvature) {
          // An indefinite tangent: CG with the probe's curvature projected away, then (still
          // indefinite) with the PSD-projected tangent (what full Newton would factorise).
          // Most need only the first (docs/benchmarks.md, "The solver's constants").
          ++timings_.psd_fallbacks;
          if (probe_tangent_on_elastic(u_, /*psd_only=*/true)) {
            constrain_values();
            cg = preconditioned_cg();
          }
          if (cg == CgOutcome::kNegativeCurvature) {
            double projected_energy = 0;
            assemble(u_, /*project_psd=*/true, &projected_energy);
            constrain_values();
            cg = preconditioned_cg();
          }
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
        back_substitute(*factor_, -r_, &du_);
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
      const double longest = longest_node_step(du_), most = boundary_->longest_step_m();
      double alpha = longest > most ? most / longest : 1.0;
      bool accepted = false;
      bool any_finite = false;
      for (int ls = 0; ls < kMaxLineSearch; ++ls, alpha *= 0.5) {
        accepted_step = alpha * longest;
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
    drift += accepted_step;
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
  back_substitute(*factor_, cg_r_, &cg_z_, kSinglePrecisionPreconditioner);
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
    back_substitute(*factor_, cg_r_, &cg_z_, kSinglePrecisionPreconditioner);
    const double rz_next = cg_r_.dot(cg_z_);
    cg_p_ = cg_z_ + (rz_next / rz) * cg_p_;
    rz = rz_next;
  }
  timings_.solve += seconds_since(start);
  return outcome;
}

}  // namespace hapstate
