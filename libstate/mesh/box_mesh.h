// Structured tetrahedral grids: the shared 6-tets-per-cell layout (TetGrid) and, built on it,
// the synthetic box mesh for tests, benchmarks and examples. The carving fallback for
// self-intersecting surfaces (carve.h) cuts its volume meshes out of the same grid.
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

#include <array>

namespace hapstate {

// Box [origin, origin + size] split into nx*ny*nz hexahedral cells, each cut into 6 tets that
// all share the cell's main diagonal (corner 0 -> corner 7), so neighbouring cells match face
// to face. Ids: node (i,j,k) = i + (nx+1)*(j + (ny+1)*k), cell (i,j,k) = i + nx*(j + ny*k),
// tet = 6*cell + local (0..5). For positive sizes every tet is positively oriented.
struct TetGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  int nx = 1;
  int ny = 1;
  int nz = 1;

  int num_nodes() const { return (nx + 1) * (ny + 1) * (nz + 1); }
  int num_cells() const { return nx * ny * nz; }
  int num_tets() const { return 6 * num_cells(); }
  int node_id(int i, int j, int k) const { return i + (nx + 1) * (j + (ny + 1) * k); }
  int cell_id(int i, int j, int k) const { return i + nx * (j + ny * k); }
  std::array<int, 3> node_index(int node) const;
  std::array<int, 3> cell_index(int cell) const;
  // Position of node (i,j,k): origin + size * (i/nx, j/ny, k/nz) (exact at the far faces).
  Eigen::Vector3d node(int i, int j, int k) const;
  Eigen::Vector3d node(int id) const;
  // The four node ids of tet `local` (0..5) of cell (i,j,k), positively oriented.
  std::array<int, 4> tet(int i, int j, int k, int local) const;
  std::array<int, 4> tet(int id) const;
  // Ids of the (up to 24) tets that contain node `id`, in increasing order.
  int tets_around_node(int id, std::array<int, 24>* out) const;
};

// Box [origin, origin + size] split into nx*ny*nz cells of 6 tetrahedra each (the TetGrid
// layout). Validated: positive orientation, boundary surface built. Groups "xmin", "xmax",
// "ymin", "ymax", "zmin", "zmax" hold the nodes on each face of the box.
Mesh make_box_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& size, int nx, int ny,
                   int nz);

}  // namespace hapstate
