// In-memory tetrahedral mesh: reference node positions, 4-node tets, boundary triangles and
// named node groups. Lengths are in the mesh file's own units (see scene mesh.unit).
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace hapstate {

using Tets = Eigen::Matrix<int, 4, Eigen::Dynamic>;
using Triangles = Eigen::Matrix<int, 3, Eigen::Dynamic>;

struct Mesh {
  Eigen::Matrix3Xd nodes;  // reference positions, one column per node (0-based ids in file order)
  Tets tets;               // node ids; every tet positively oriented (det[b-a, c-a, d-a] > 0)
  Triangles surface;       // boundary faces (faces used by exactly one tet), outward normals
  // Physical groups of the file (Gmsh physical names or numbers, Medit refs, ...): group name ->
  // sorted unique node ids of every element in the group.
  std::map<std::string, std::vector<int>> groups;
  std::string source;  // file the mesh came from (for error messages)

  int num_nodes() const { return static_cast<int>(nodes.cols()); }
  int num_tets() const { return static_cast<int>(tets.cols()); }
};

}  // namespace hapstate
