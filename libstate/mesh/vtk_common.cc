#include "mesh/vtk_common.h"

#include "util/error.h"

#include <unordered_map>

namespace hapstate {

VtkCellRole vtk_cell_role(long long type) {
  switch (type) {
    case kVtkTetra:
      return VtkCellRole::kTet;
    case 1:
    case 2:
    case 3:
    case 4:
    case 5:
    case 6:
    case 7:
    case 8:
    case 9:  // vertex .. quad
    case 21:
    case 22:
    case 23:
    case 28:
    case 30:
    case 34:
    case 35:
    case 36:  // quadratic 1-D/2-D
    case 68:
    case 69:
    case 70:
    case 75:
    case 76:
    case 77:  // Lagrange/Bezier 1-D/2-D
      return VtkCellRole::kLowerDimension;
    case 24:
    case 71:
    case 78:  // quadratic, Lagrange, Bezier tetrahedron
      return VtkCellRole::kHigherOrderTet;
    default:
      return VtkCellRole::kUnsupported;
  }
}

void add_vtk_cells(const VtkCells& cells, int first_point, int num_points,
                   const std::function<std::string(std::size_t)>& where, RawMesh* mesh) {
  const std::size_t n = cells.types.size();
  for (std::size_t c = 0; c < n; ++c) {
    const long long begin = cells.offsets[c];
    const long long end = cells.offsets[c + 1];
    for (long long k = begin; k < end; ++k) {
      const long long id = cells.connectivity[static_cast<std::size_t>(k)];
      if (id < 0 || id >= num_points) {
        throw InputError(where(c) + ": cell " + std::to_string(c) + " references point " +
                         std::to_string(id) + ", but there are only " + std::to_string(num_points) +
                         " points (0-based; missing node)");
      }
    }
    const long long type = cells.types[c];
    switch (vtk_cell_role(type)) {
      case VtkCellRole::kTet: {
        if (end - begin != 4) {
          throw InputError(where(c) + ": cell " + std::to_string(c) + " is a VTK_TETRA with " +
                           std::to_string(end - begin) + " points (expected 4)");
        }
        const long long* p = &cells.connectivity[static_cast<std::size_t>(begin)];
        mesh->tets.push_back(
            {first_point + static_cast<int>(p[0]), first_point + static_cast<int>(p[1]),
             first_point + static_cast<int>(p[2]), first_point + static_cast<int>(p[3])});
        break;
      }
      case VtkCellRole::kLowerDimension:
        break;
      case VtkCellRole::kHigherOrderTet:
        throw InputError(where(c) + ": cell " + std::to_string(c) +
                         " has unsupported higher-order cell type " + std::to_string(type) +
                         "; only linear tetrahedra (VTK_TETRA = 10) are supported");
      case VtkCellRole::kUnsupported:
        throw InputError(where(c) + ": cell " + std::to_string(c) +
                         " has unsupported or unknown cell type " + std::to_string(type) +
                         "; only linear tetrahedra (VTK_TETRA = 10) are supported as volume cells");
    }
  }
  for (const auto& [name, values] : cells.labels) {
    std::unordered_map<long long, std::vector<int>*> by_value;
    for (std::size_t c = 0; c < n; ++c) {
      std::vector<int>*& group = by_value[values[c]];
      if (group == nullptr) group = &mesh->groups[name + ":" + std::to_string(values[c])];
      auto& g = *group;
      for (long long k = cells.offsets[c]; k < cells.offsets[c + 1]; ++k) {
        g.push_back(first_point +
                    static_cast<int>(cells.connectivity[static_cast<std::size_t>(k)]));
      }
    }
  }
}

}  // namespace hapstate
