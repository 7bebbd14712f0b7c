// A scene bound to its mesh: everything the mechanics needs to solve a probe path.
// Lengths are in mesh units (scene units); `unit` converts them to metres for the FEM.
#pragma once

#include "fem/constraints.h"
#include "fem/loads.h"
#include "material/material.h"
#include "mesh/mesh.h"
#include "problem/solver_options.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace hapstate {

// The contact probe (scene probe.mode = "contact"): a rigid sphere whose centre at rest is
// Problem::probe_rest. See docs/contact.md for the model.
struct ContactSphere {
  double radius = 0;  // mesh units, > 0
  // kNone (default): frictionless sliding against the surface triangles
  // (solver/sliding_contact.h); kStick: surface nodes stick to the sphere where it caught them
  // (solver/contact_set.h).
  Friction friction = Friction::kNone;
  std::vector<int> candidates;  // surface nodes the sphere may touch (none of their DOFs fixed),
                                // ascending
};

struct Problem {
  Mesh mesh;                   // as imported, mesh units
  double unit = 1.0;           // metres per mesh unit (scene mesh.unit)
  MaterialConstants material;  // resolved constants (from E, nu or given directly)
  Constraints constraints;     // fixed DOFs (union of selectors) and grabbed probe nodes
  Eigen::Vector3d probe_rest =
      Eigen::Vector3d::Zero();  // probe position at rest, mesh units:
                                // the grabbed node, or the centroid of the grabbed patch
  double max_force = 0;         // N, device force limit
  SolverOptions solver;
  // Set for a contact probe: then constraints.probe_nodes is empty and no DOF is kProbe; the
  // touched nodes are decided by the solver at each probe position.
  std::optional<ContactSphere> contact;
  // Gravity and elastic supports (scene material.density, [loads], [[support]]); empty: none.
  BodyLoads loads;
  // The loaded rest state: the equilibrium under `loads` with the probe attached to nothing
  // (metres, one value per DOF, relative to the mesh as drawn); empty: u = 0 (no body force).
  // The zero configuration of the state space and the state PathSolver::reset() returns to.
  Eigen::VectorXd rest_m;
  // How far the rest state carries the grab point (mesh units): probe_rest is the grabbed
  // nodes' centroid in the rest state, probe_rest - probe_sag their centroid as drawn; an
  // explicit grid.box is shifted by it. Zero for a contact probe and without loads.
  Eigen::Vector3d probe_sag = Eigen::Vector3d::Zero();
};

// The rest state's displacements in mesh units, 3 per node (zeros without a body force): the
// vector u of the zero configuration, which stores no blob of its own.
inline std::vector<double> rest_displacements(const Problem& problem) {
  std::vector<double> u(3 * static_cast<std::size_t>(problem.mesh.num_nodes()), 0.0);
  if (problem.rest_m.size() == static_cast<Eigen::Index>(u.size()))
    for (std::size_t d = 0; d < u.size(); ++d) u[d] = problem.rest_m[d] / problem.unit;
  return u;
}

}  // namespace hapstate
