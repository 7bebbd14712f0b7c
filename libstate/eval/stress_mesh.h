// Geometry for the numerical stress suite (eval/stress_case.h): tetrahedron quality, a box mesh
// with slivers, and the principal stretches of a deformed mesh.
#pragma once

#include "mesh/mesh.h"

#include <Eigen/Core>

#include <cstdint>

namespace hapstate {

// Normalised radius ratio q = 3 r_in / r_circ of the tet with corners a, b, c, d: 1 for the
// regular tetrahedron, -> 0 for a degenerate one (slivers, needles, caps); negative when the tet
// is inverted (the sign of its volume). Scale-invariant.
double tet_quality(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d);

// Smallest q over the mesh's tets (reference positions).
double min_tet_quality(const Mesh& mesh);

// The mesh with its interior nodes (no surface node moves, so the boundary, its groups and its
// surface triangles stay those of `mesh`) moved by seeded pseudo-random offsets of up to
// `amplitude` x the smallest cell size along each axis `spacing`, each move kept only if every
// tet around the node keeps q >= `floor` (> 0: no move inverts or flattens a tet). The same
// seed gives the same mesh on every platform (its own generator, no std distributions).
Mesh perturb_interior(const Mesh& mesh, double amplitude, double floor, std::uint64_t seed);

// Deformation measures over the tets of `mesh` displaced by `u` (3 x nodes, mesh units):
// the largest and smallest principal stretch (singular values of F = I + grad u, per tet) and the
// smallest det F. A rigid motion gives 1, 1, 1.
struct StretchRange {
  double max_stretch = 1, min_stretch = 1, min_jacobian = 1;
};
StretchRange stretch_range(const Mesh& mesh, const Eigen::Matrix3Xd& u);

}  // namespace hapstate
