// External loads on the body besides the probe: a dead body force (gravity: density x g,
// integrated over the reference volume) and elastic supports (springs from each supported DOF
// to its position in the mesh as drawn). Both enter the potential energy,
//   Pi(u) = sum_e V_e W(F_e) - s b.u + 1/2 sum_d k_d u_d^2,
// so the force and tangent stay consistent (fem/assembler.h adds them). s is the load scale of
// the incremental loading that finds the loaded rest state (1 otherwise; the supports are not
// scaled). Both vectors have one value per DOF (3 * node + component) or are empty (none).
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace hapstate {

struct BodyLoads {
  Eigen::VectorXd force;   // b [N], the body force lumped to the nodes (P1: V/4 of each tet)
  Eigen::VectorXd spring;  // k [N/m], the supports' stiffness per DOF (>= 0)
  // What `force` was made of (gravity_force), for exports (ccx/deck.h): kg/m^3 and m/s^2.
  double density = 0;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  bool has_force() const { return force.size() > 0; }
  bool has_springs() const { return spring.size() > 0; }
  bool empty() const { return !has_force() && !has_springs(); }
};

// The dead weight of a body of uniform density [kg/m^3] under gravity g [m/s^2]: per node a
// quarter of each of its tets' mass times g (exact for P1 elements), positions in metres.
Eigen::VectorXd gravity_force(const Eigen::Matrix3Xd& positions_m, const Tets& tets, double density,
                              const Eigen::Vector3d& gravity);

// Adds to `spring` (one value per DOF) an elastic foundation of `stiffness` [N/m^3: pressure per
// metre of displacement] over the surface triangles whose three corners are all `selected`: each
// such triangle's area (m^2) times the stiffness, a third to each corner, in the components of
// `dofs`. Returns how many triangles it covered.
int add_surface_springs(const Eigen::Matrix3Xd& positions_m, const Triangles& surface,
                        const std::vector<bool>& selected, double stiffness,
                        const std::array<bool, 3>& dofs, Eigen::VectorXd* spring);

}  // namespace hapstate
