#include "mesh/box_mesh.h"

#include "mesh/raw_mesh.h"
#include "mesh/validate.h"

#include <array>

namespace hapstate {

Mesh make_box_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& size, int nx, int ny,
                   int nz) {
  RawMesh raw;
  raw.source = "box mesh";
  const auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        raw.xyz.push_back(origin.x() + size.x() * i / nx);
        raw.xyz.push_back(origin.y() + size.y() * j / ny);
        raw.xyz.push_back(origin.z() + size.z() * k / nz);
        const int n = id(i, j, k);
        if (i == 0) raw.add_to_group("xmin", &n, 1);
        if (i == nx) raw.add_to_group("xmax", &n, 1);
        if (j == 0) raw.add_to_group("ymin", &n, 1);
        if (j == ny) raw.add_to_group("ymax", &n, 1);
        if (k == 0) raw.add_to_group("zmin", &n, 1);
        if (k == nz) raw.add_to_group("zmax", &n, 1);
      }
  // Corners of a cell by bit pattern (x = bit 0, y = bit 1, z = bit 2); six tets around 0-7.
  static constexpr std::array<std::array<int, 4>, 6> kCellTets = {{
      {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& t : kCellTets) {
          std::array<int, 4> tet;
          for (int a = 0; a < 4; ++a) {
            const int c = t[a];
            tet[a] = id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          }
          raw.tets.push_back(tet);  // validate_mesh fixes the orientation
        }
  return validate_mesh(std::move(raw), nullptr);
}

}  // namespace hapstate
