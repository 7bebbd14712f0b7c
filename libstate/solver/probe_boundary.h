// The probe's boundary condition inside the path solver: the one place where the three probes
// differ (docs/mechanics.md, docs/contact.md). PathSolver holds one and never asks which it is.
//  - grab: the grabbed DOFs are prescribed, u = t (probe_boundary.cc);
//  - sticking contact: the DOFs of the nodes the sphere touches follow it, u = base + t; after
//    every Newton solve an active-set loop releases adhesive nodes and adds penetrating ones
//    (stick_boundary.cc, over solver/contact_set.h);
//  - frictionless contact: nothing is prescribed; the sphere adds the augmented-Lagrangian energy
//    of the gaps of the surface triangles, whose multipliers are updated after every Newton
//    solve until the gaps close (sliding_boundary.cc, over solver/sliding_contact.h).
// Every operation takes the probe displacement t (mesh units, relative to Problem::probe_rest);
// u and forces are in metres and N, as in the solver.
#pragma once

#include "fem/assembler.h"
#include "problem/problem.h"
#include "problem/solver_options.h"
#include "solver/contact_timings.h"

#include <Eigen/Core>

#include <limits>
#include <memory>
#include <vector>

namespace hapstate {

struct MoveResult;

// The DOFs that follow the probe in a state: per DOF its role, the component of t it follows
// (-1: none) and its value at t = 0 [m]; a DOF with component c >= 0 has u = base + unit * t_c.
struct Prescription {
  std::vector<DofRole> role;
  std::vector<int> component;
  Eigen::VectorXd base;
};

// The boundary's part of a state besides u (what a cut-back saves and restores): the touched
// nodes and their anchors (sticking), the multipliers of the surface triangles (frictionless).
struct BoundaryState {
  std::vector<int> touched;
  std::vector<Eigen::Vector3d> anchors;
  std::vector<double> multipliers;
  bool operator==(const BoundaryState&) const = default;
};

// What a boundary's settling loop may ask of the solver.
class SettleHost {
 public:
  virtual Eigen::VectorXd& state() = 0;              // u [m]
  virtual const Eigen::VectorXd& force() const = 0;  // internal force at u after the last solve
  virtual void prescription_changed(const Eigen::Vector3d& t) = 0;  // re-read, set probe DOFs
  // Newton at the probe position of the solve under way; have_factor: the solver's factor is of
  // a nearby state and may precondition it.
  virtual bool newton(double rel_tol, MoveResult* result, bool have_factor) = 0;

 protected:
  ~SettleHost() = default;
};

class ProbeBoundary {
 public:
  virtual ~ProbeBoundary() = default;

  // --- State.
  // Back to the rest state (nothing touched, no multiplier).
  virtual void reset() {}
  // The boundary's part of a stored state at u [m], t: the touched nodes (sticking) or the
  // sparse multipliers, pairs (surface triangle, N) (frictionless); the other is ignored.
  // Throws InputError (nothing changed) for a node that is not a candidate or pairs that do not
  // fit the mesh.
  virtual void set_state(const Eigen::VectorXd& /*u_m*/, const Eigen::Vector3d& /*t*/,
                         const std::vector<int>& /*touched*/,
                         const std::vector<double>& /*multipliers*/) {}
  virtual BoundaryState save() const { return {}; }
  virtual void restore(const BoundaryState& /*state*/) {}
  // The nodes the sphere holds (sticking) or presses (frictionless: the corners of the loaded
  // triangles) at u, t, ascending; empty for a grab probe.
  virtual std::vector<int> touched_nodes(const Eigen::VectorXd& /*u_m*/,
                                         const Eigen::Vector3d& /*t*/) const {
    return {};
  }
  // The non-zero multipliers as pairs (surface triangle, N) (frictionless), else empty.
  virtual std::vector<double> stored_multipliers() const { return {}; }
  virtual const ContactTimings* timings() const { return nullptr; }

  // --- Prescribed DOFs: adds the probe's DOFs to `p` (which holds the scene's fixed DOFs).
  virtual void prescribe(Prescription* /*p*/) const {}

  // --- The probe's own potential energy Psi(u, t) (frictionless contact; else none).
  // Adds dPsi/du to f; returns Psi [J].
  virtual double add_force(const Eigen::VectorXd& /*u_m*/, const Eigen::Vector3d& /*t*/,
                           Eigen::VectorXd* /*f*/) const {
    return 0;
  }
  // Adds d2Psi/du2 to the tangent's values (pattern order). psd_only: its positive
  // semi-definite part. for_stiffness: the active gaps as the exact constraints they converge to.
  virtual void add_tangent(const Eigen::VectorXd& /*u_m*/, const Eigen::Vector3d& /*t*/,
                           std::vector<double>* /*k_values*/, bool /*psd_only*/,
                           bool /*for_stiffness*/) const {}
  // Adds d2Psi/du dc (num_dofs x 3) and d2Psi/dc2 [N/m], c the centre in metres.
  virtual void add_coupling(const Eigen::VectorXd& /*u_m*/, const Eigen::Vector3d& /*t*/,
                            Eigen::Matrix<double, Eigen::Dynamic, 3>* /*k_uc*/,
                            Eigen::Matrix3d* /*k_cc*/, bool /*for_stiffness*/) const {}
  // The force the user feels from the energy, -dPsi/dc [N]; false: it is minus the reactions of
  // the prescribed DOFs.
  virtual bool force_from_energy() const { return false; }
  virtual Eigen::Vector3d force_on_probe(const Eigen::VectorXd& /*u_m*/,
                                         const Eigen::Vector3d& /*t*/) const {
    return Eigen::Vector3d::Zero();
  }

  // --- How a move is solved.
  // Whether the inexact Newton of the fast algorithm may be used (sticking: its decisions need
  // exact reactions).
  virtual bool allows_inexact_newton() const { return true; }
  // Whether every sub-step is solved to the full tolerance (sticking), not only the last.
  virtual bool converges_every_substep() const { return false; }
  // The longest step [m] of the probe in one sub-step, and of any node in one Newton iteration.
  virtual double longest_step_m() const { return std::numeric_limits<double>::infinity(); }
  // Whether a converged move's last Newton force is the state's internal force (grab).
  virtual bool keeps_newton_force() const { return true; }
  // At the start of a sub-step from (u, t_from) to t_to: true when it needs no predictor and
  // Newton solve (*ok then says whether it succeeded): the body at rest with nothing within the
  // sphere's reach.
  virtual bool settled_without_solve(SettleHost& /*host*/, const Eigen::Vector3d& /*t_to*/,
                                     const SolverOptions& /*options*/, MoveResult* /*result*/,
                                     bool* /*ok*/) {
    return false;
  }
  // The predictor's load of a sub-step: adds d2Psi/du dc * dc to k_dt (dc [m]).
  virtual void add_predictor_load(const Eigen::VectorXd& /*u_m*/, const Eigen::Vector3d& /*t*/,
                                  const Eigen::Vector3d& /*dc_m*/,
                                  Eigen::VectorXd* /*k_dt*/) const {}
  // The relative tolerance of a sub-step's first Newton solve, before settle() (rel_tol: the
  // sub-step's; last: the move's last sub-step). A boundary whose settling re-solves anyway may
  // ask for less; settle() then ends with a solve to rel_tol.
  virtual double first_solve_tolerance(double rel_tol, bool /*last*/) const { return rel_tol; }
  // After the Newton solve of a sub-step at t: the active set (touched nodes or multipliers)
  // is updated and re-solved until it is stable; last: the move's last sub-step.
  virtual bool settle(SettleHost& /*host*/, const Eigen::Vector3d& /*t*/, double /*rel_tol*/,
                      bool /*last*/, const SolverOptions& /*options*/, MoveResult* /*result*/) {
    return true;
  }
};

// The boundary of `problem`'s probe. `assembler` and `role` (the scene's roles, nodes used by no
// tet fixed) give the frictionless penalty's stiffness scale.
std::unique_ptr<ProbeBoundary> make_probe_boundary(const Problem& problem,
                                                   const Assembler& assembler,
                                                   const std::vector<DofRole>& role);
// The two contact boundaries (stick_boundary.cc, sliding_boundary.cc).
std::unique_ptr<ProbeBoundary> make_stick_boundary(const Problem& problem);
std::unique_ptr<ProbeBoundary> make_sliding_boundary(const Problem& problem,
                                                     const Assembler& assembler,
                                                     const std::vector<DofRole>& role);

}  // namespace hapstate
