// How the probe loads the body at a check-point: the interface both probe modes fit (grab now,
// contact later). The expansion only talks to the probe through it.
#pragma once

#include "scene/problem.h"
#include "scene/scene.h"
#include "solver/path_solver.h"

#include <Eigen/Core>

#include <memory>
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
  // The prescribed DOFs and values with the probe at position p (mesh units).
  virtual ProbeLoad load_at(const Eigen::Vector3d& p) const = 0;
  // Puts `solver` into the state of a stored configuration: displacements u (mesh units, 3 per
  // node) with the probe at position p.
  virtual void set_state(PathSolver& solver, const std::vector<double>& u,
                         const Eigen::Vector3d& p) const = 0;
  // Moves the probe of `solver` from its current state to position p.
  virtual MoveResult move_to(PathSolver& solver, const Eigen::Vector3d& p) const = 0;
  // Whether the probe at p leaves the body undeformed: such a check-point holds a zero
  // configuration (grab: only the rest position).
  virtual bool holds_zero_configuration(const Eigen::Vector3d& p) const = 0;
};

// The grab probe: the grabbed nodes translate rigidly with the probe, t = p - probe_rest on the
// grabbed components. Keeps a reference to `problem`, which must outlive it.
std::unique_ptr<ProbeModel> make_probe_model(const Problem& problem, ProbeMode mode);

}  // namespace hapstate
