// Pieces shared by the legacy VTK and the VTK XML readers: cell type classification and how
// cells become tets and group members.
#pragma once

#include "mesh/raw_mesh.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hapstate {

inline constexpr int kVtkTetra = 10;

// What the importer does with a VTK cell type.
enum class VtkCellRole { kTet, kLowerDimension, kHigherOrderTet, kUnsupported };
VtkCellRole vtk_cell_role(long long type);

// Cells of an unstructured grid as read from a file, before they are checked.
struct VtkCells {
  std::vector<long long> connectivity;  // point ids of all cells, concatenated
  std::vector<long long> offsets;       // cell c uses connectivity[offsets[c] .. offsets[c+1])
  std::vector<long long> types;         // VTK cell type per cell
  // Integer cell-data arrays with one component: array name -> value per cell.
  std::vector<std::pair<std::string, std::vector<long long>>> labels;
};

// Appends the tets of `cells` to `mesh` (point ids offset by `first_point`, `num_points` in
// this piece) and the groups "<array>:<value>" of its integer cell-data arrays. `where(c)`
// gives "file:line" for cell c in error messages. Throws InputError for a point id out of range,
// a tet without 4 points, and volume cells other than linear tets.
void add_vtk_cells(const VtkCells& cells, int first_point, int num_points,
                   const std::function<std::string(std::size_t)>& where, RawMesh* mesh);

}  // namespace hapstate
