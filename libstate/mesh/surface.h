// Closed triangle surfaces (STL, OBJ) and their tetrahedralisation (Gmsh, or carving a grid).
#pragma once

#include "mesh/raw_mesh.h"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hapstate {

struct TriangleSurface {
  std::string source;
  std::vector<double> xyz;                // 3 per vertex
  std::vector<std::array<int, 3>> faces;  // 0-based vertex ids
  std::vector<int> face_lines;            // line of each face in the file (0 for binary STL)
};

// Parses a Wavefront OBJ (v and f lines; polygons are fan-triangulated; other lines ignored).
TriangleSurface parse_obj(std::string_view text, const std::string& source);
// Parses an ASCII or binary STL; vertices with identical coordinates are merged.
TriangleSurface parse_stl(std::string_view text, const std::string& source);

// Throws InputError unless `s` is a closed, consistently oriented 2-manifold (each edge in
// exactly two faces, once in each direction; no face repeating a vertex): names the face's
// file:line ("open surface: edge (a, b) ... belongs to only one face" for holes).
void check_surface_topology(const TriangleSurface& s);

// Where a surface crosses itself: an edge crossing a face that shares none of its vertices.
struct SelfIntersection {
  Eigen::Vector3d point;      // where the edge meets the face
  std::string face;           // file:line of the crossed face
  std::array<int, 2> edge{};  // 0-based vertex ids of the crossing edge
  std::string edge_face;      // file:line of a face using that edge
  std::string near() const;   // "(x, y, z)"
  // "file:line: self-intersecting surface: this face is crossed by the edge (...) near (...)".
  std::string message() const;
};

// The first self-intersection found (grid-accelerated), or none.
std::optional<SelfIntersection> find_self_intersection(const TriangleSurface& s);

// check_surface_topology, then throws InputError with SelfIntersection::message() if the
// surface crosses itself.
void check_closed_surface(const TriangleSurface& s);

// Fills the inside of a closed surface with tets using Gmsh (surface triangles kept as the
// boundary). Serialised with a global mutex; Gmsh errors become InputError.
RawMesh tetrahedralize_surface(const TriangleSurface& s);

// The importer's path for STL/OBJ: check_surface_topology (an open or non-manifold surface is an
// InputError), then Gmsh if the surface does not cross itself; a self-intersecting surface, or
// one Gmsh fails on, is carved out of a tet grid instead (carve.h) and the returned mesh carries a
// warning saying where the surface crosses itself (or what Gmsh said), the cell size, the tet
// count and the carved/enclosed volume ratio.
RawMesh fill_closed_surface(const TriangleSurface& s);

}  // namespace hapstate
