// Synthetic meshes for tests, benchmarks and examples: a structured box of tetrahedra.
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

namespace hapstate {

// Box [origin, origin + size] split into nx*ny*nz cells of 6 tetrahedra each (all sharing the
// cell's main diagonal, so neighbouring cells match). Validated: positive orientation,
// boundary surface built. Groups "xmin", "xmax", "ymin", "ymax", "zmin", "zmax" hold the
// nodes on each face of the box.
Mesh make_box_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& size, int nx, int ny,
                   int nz);

}  // namespace hapstate
