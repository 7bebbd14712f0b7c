// Geometric node selection on a mesh (mesh units), used to bind [[fixed]] and [probe].
#pragma once

#include "mesh/mesh.h"
#include "scene/scene.h"

#include <Eigen/Core>

#include <vector>

namespace hapstate {

// Nodes inside the closed box (min <= X <= max componentwise), ascending ids.
std::vector<int> nodes_in_box(const Mesh& mesh, const Box& box);

// Nodes with |dot(X - point, normal / |normal|)| <= tolerance, ascending ids. The tolerance
// defaults to kPlaneRelativeTolerance x the mesh bounding-box diagonal.
std::vector<int> nodes_on_plane(const Mesh& mesh, const PlaneSelector& plane);
inline constexpr double kPlaneRelativeTolerance = 1e-6;

// Nodes of the boundary triangles (Mesh::surface), ascending ids.
std::vector<int> surface_nodes(const Mesh& mesh);

// Marks nodes used by at least one tet.
std::vector<bool> used_nodes(const Mesh& mesh);

// The node used by a tet nearest to `point` (Euclidean; ties -> smallest id), or -1 if no
// node is used by a tet. Surface and interior nodes alike.
int nearest_node(const Mesh& mesh, const Eigen::Vector3d& point);

// Surface nodes with |X - point| <= radius, ascending ids.
std::vector<int> surface_nodes_within(const Mesh& mesh, const Eigen::Vector3d& point,
                                      double radius);

}  // namespace hapstate
