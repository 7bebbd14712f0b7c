// Test helper: a structured box of tets built in code (no mesh reader needed).
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

namespace hapstate::testing {

// nx x ny x nz nodes at offset + (i, j, k) * h, node id = i + nx * (j + ny * k); each cell
// split into 6 positively oriented tets around its main diagonal; surface = faces used once.
Mesh make_box_mesh(int nx, int ny, int nz, double h = 1.0,
                   const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());

// Appends `b` to `a` (ids of b shifted), giving a mesh with two disconnected parts.
Mesh merge_meshes(const Mesh& a, const Mesh& b);

inline int box_node(int i, int j, int k, int nx, int ny) { return i + nx * (j + ny * k); }

}  // namespace hapstate::testing
