// Mesh import: reads any supported tetrahedral mesh format (chosen by extension and content),
// or tetrahedralises a closed triangle surface (STL/OBJ), then validates the result.
#pragma once

#include "mesh/mesh.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

// What validation found and repaired while importing a mesh.
struct MeshReport {
  int reoriented = 0;    // negatively oriented tets that were flipped
  int degenerate = 0;    // zero-volume tets (removed)
  int duplicate = 0;     // tets repeating another tet's node set (removed)
  int unreferenced = 0;  // nodes used by no tet (kept, reported)
  std::vector<std::string>
      warnings;  // one line each, for the user (each kind listed up to 20 times)
  std::vector<int> degenerate_tets;  // file-order indices (0-based) of the removed degenerate tets
  std::vector<int> duplicate_tets;   // file-order indices of the removed later copies
  std::vector<int> unreferenced_nodes;  // 0-based node ids used by no tet
  std::string format;                   // detected format, e.g. "gmsh-4.1-binary", "vtu"
};

// Reads `file`, validates it and builds the boundary surface. Throws InputError naming
// file:line and what was expected for a malformed file.
// Formats (by extension, checked against the header): .msh (Gmsh 1, 2.2, 4.1; ASCII/binary),
// .vtk (legacy UNSTRUCTURED_GRID), .vtu (VTK XML), .mesh (Medit ASCII), .node/.ele (TetGen),
// .stl/.obj (closed triangle surface, tetrahedralised with Gmsh, or carved out of a tet grid if
// it crosses itself: fill_closed_surface). See docs/mesh-formats.md.
Mesh load_mesh(const std::filesystem::path& file, MeshReport* report = nullptr);

}  // namespace hapstate
