// Rigid-body check: do the constrained DOFs (fixed + probe) remove every rigid-body motion of
// every connected part of the mesh? If not, the static problem is singular.
#pragma once

#include "fem/constraints.h"
#include "mesh/mesh.h"

#include <string>
#include <vector>

namespace hapstate {

// Connected components of the mesh through shared tet nodes: node ids (ascending) of each,
// components ordered by their smallest node id. Nodes used by no tet belong to none.
std::vector<std::vector<int>> connected_components(const Mesh& mesh);

// One component whose constraints leave rigid-body modes free.
struct FreeRigidModes {
  int component = 0;  // index into connected_components()
  int num_nodes = 0;
  int free_modes = 0;   // 1..6
  std::string example;  // one free motion, e.g. "rotation about x through (0, 0.5, 0.5)"
};

// For each component: the 3 translations and 3 infinitesimal rotations about its centroid,
// evaluated at its constrained DOFs (role != kFree) with lengths scaled by the component's
// radius, form a (#DOFs x 6) matrix; its numerical rank (singular values above
// kRigidRankTolerance x the largest) must be 6. Returns the components where it is not.
std::vector<FreeRigidModes> free_rigid_modes(const Mesh& mesh, const std::vector<DofRole>& role);
inline constexpr double kRigidRankTolerance = 1e-8;

}  // namespace hapstate
