// Closed triangle surfaces (STL, OBJ) and their tetrahedralisation with Gmsh.
#pragma once

#include "mesh/raw_mesh.h"

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace hapstate {

struct TriangleSurface {
  std::string source;
  std::vector<double> xyz;                  // 3 per vertex
  std::vector<std::array<int, 3>> faces;    // 0-based vertex ids
  std::vector<int> face_lines;              // line of each face in the file (0 for binary STL)
};

// Parses a Wavefront OBJ (v and f lines; polygons are fan-triangulated; other lines ignored).
TriangleSurface parse_obj(std::string_view text, const std::string& source);
// Parses an ASCII or binary STL; vertices with identical coordinates are merged.
TriangleSurface parse_stl(std::string_view text, const std::string& source);

// Throws InputError unless `s` is a closed, consistently oriented 2-manifold without
// self-intersections (an edge crossing a face it does not touch): names the face's file:line.
void check_closed_surface(const TriangleSurface& s);

// Fills the inside of a closed surface with tets using Gmsh (surface triangles kept as the
// boundary). Serialised with a global mutex; Gmsh errors become InputError.
RawMesh tetrahedralize_surface(const TriangleSurface& s);

}  // namespace hapstate
