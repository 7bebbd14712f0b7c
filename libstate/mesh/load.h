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
  int reoriented = 0;     // negatively oriented tets that were flipped
  int degenerate = 0;     // zero-volume tets (removed)
  int duplicate = 0;      // tets repeating another tet's node set (removed)
  int unreferenced = 0;   // nodes used by no tet (kept, reported)
  std::vector<std::string> warnings;  // one line each, for the user
};

// Reads `file`, validates it and builds the boundary surface. Throws InputError naming
// file:line and what was expected for a malformed file.
Mesh load_mesh(const std::filesystem::path& file, MeshReport* report = nullptr);

}  // namespace hapstate
