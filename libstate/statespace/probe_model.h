// How the probe loads the body at a check-point: the interface both probe modes fit (grab and
// contact). The expansion only talks to the probe through it.
#pragma once

#include "problem/problem.h"
#include "scene/scene.h"
#include "solver/path_solver.h"
#include "statespace/level_match.h"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <vector>

namespace hapstate {

// Prescribed displacements for one probe position: DOFs (3 * node + component, ascending) and
// their values (mesh units). Stored with each configuration as its vector t.
struct ProbeLoad {
  std::vector<int> dofs;
  std::vector<double> values;
};

class ProbeModel {
 public:
  virtual ~ProbeModel() = default;

  // The probe position at rest (mesh units); the grid is aligned on it.
  virtual Eigen::Vector3d rest_position() const = 0;
  // The prescribed DOFs and values of `solver`'s current state, its probe at p (grab: the
  // grabbed DOFs, t = p - rest; sticking contact: the three DOFs of every touched node;
  // frictionless contact: none).
  virtual ProbeLoad load_of(const PathSolver& solver, const Eigen::Vector3d& p) const = 0;
  // Puts `solver` into the state of a stored configuration `v` (u in mesh units, 3 per node;
  // sticking: the touched set; frictionless: the multipliers) with the probe at position p.
  virtual void set_state(PathSolver& solver, const ConfigVectors& v,
                         const Eigen::Vector3d& p) const = 0;
  // Moves the probe of `solver` from its current state to position p.
  MoveResult move_to(PathSolver& solver, const Eigen::Vector3d& p) const {
    return solver.move_to(p - rest_position());
  }
  // Whether the probe at p is clear of the body at rest (grab: never; contact: the sphere touches
  // nothing of the rest shape: no surface triangle within the radius when frictionless, no
  // candidate node when sticking; and its centre is outside the rest body: a sphere deep inside
  // touches nothing either, but only pushing gets it there). Such a check-point is free: it
  // holds the zero configuration.
  virtual bool clear_of_body(const Eigen::Vector3d& p) const = 0;
  // Whether the probe at p leaves the body undeformed: the rest position and every position
  // clear of the body. Such a check-point holds a zero configuration.
  bool holds_zero_configuration(const Eigen::Vector3d& p) const {
    return p == rest_position() || clear_of_body(p);
  }
  // The start of a path at p: where the probe at p is clear of the body, `solver` is put at rest
  // with its probe there (a contact path may start anywhere clear of the body) and true is
  // returned; else nothing changes (the path starts from the solver's state, at rest: the probe
  // at its rest position).
  bool start_path_at(PathSolver& solver, const Eigen::Vector3d& p) const {
    if (!clear_of_body(p)) return false;
    solver.set_state(solver.rest_state_m(), p - rest_position());
    return true;
  }
  // Whether moving the probe from a to b with the body at rest keeps it at rest, so the move
  // needs no solve (grab: never; contact: the sphere sweeps past the rest shape: every surface
  // triangle when frictionless, every candidate node when sticking).
  virtual bool trivial_move(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const = 0;
  // The probe's clearance from the body at rest at p (contact): the signed distance from p to
  // the rest surface triangles (sticking: to the nearest candidate node; negative with the
  // centre inside the rest body) minus the radius (sticking: the reach), > 0 where the probe is
  // clear of the body, and its gradient. Exact where the nearest surface point is within
  // `range` of the sphere; farther, {range, 0} outside and {-(range + radius), 0} inside. Grab:
  // nothing (the probe is never clear of the body).
  struct Clearance {
    double gap = 0;
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  };
  virtual std::optional<Clearance> clearance(const Eigen::Vector3d& p, double range) const = 0;
  // The rest surface the clearance is measured from, when it is the distance to its triangles
  // (frictionless contact): 9 per triangle (its corners, mesh units), and the radius; else none.
  struct RestSurface {
    std::vector<double> triangles;
    double radius = 0;
  };
  virtual std::optional<RestSurface> rest_surface() const { return std::nullopt; }

  // What a configuration stores besides u (statespace/level_match.h).
  virtual VectorLayout layout() const = 0;
  bool stores_touched() const { return layout().touched; }
};

// The probe of `problem` (grab; contact when problem.contact is set, frictionless or sticking).
// Keeps a reference to `problem`, which must outlive it.
std::unique_ptr<ProbeModel> make_probe_model(const Problem& problem);

}  // namespace hapstate
