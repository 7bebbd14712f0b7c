#include "mesh/box_mesh.h"

#include "mesh/raw_mesh.h"
#include "mesh/validate.h"

#include <algorithm>

namespace hapstate {
namespace {

// Corners of a cell by bit pattern (x = bit 0, y = bit 1, z = bit 2); six tets around 0-7,
// each listed with positive orientation (det[b-a, c-a, d-a] = +1 on the unit cube).
constexpr std::array<std::array<int, 4>, 6> kCellTets = {
    {{0, 1, 3, 7}, {0, 1, 7, 5}, {0, 2, 7, 3}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 7, 6}}};

}  // namespace

std::array<int, 3> TetGrid::node_index(int node) const {
  return {node % (nx + 1), (node / (nx + 1)) % (ny + 1), node / ((nx + 1) * (ny + 1))};
}

std::array<int, 3> TetGrid::cell_index(int cell) const {
  return {cell % nx, (cell / nx) % ny, cell / (nx * ny)};
}

Eigen::Vector3d TetGrid::node(int i, int j, int k) const {
  return {origin.x() + size.x() * i / nx, origin.y() + size.y() * j / ny,
          origin.z() + size.z() * k / nz};
}

Eigen::Vector3d TetGrid::node(int id) const {
  const auto [i, j, k] = node_index(id);
  return node(i, j, k);
}

std::array<int, 4> TetGrid::tet(int i, int j, int k, int local) const {
  std::array<int, 4> t{};
  for (int a = 0; a < 4; ++a) {
    const int c = kCellTets[static_cast<std::size_t>(local)][static_cast<std::size_t>(a)];
    t[static_cast<std::size_t>(a)] = node_id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
  }
  return t;
}

std::array<int, 4> TetGrid::tet(int id) const {
  const auto [i, j, k] = cell_index(id / 6);
  return tet(i, j, k, id % 6);
}

int TetGrid::tets_around_node(int id, std::array<int, 24>* out) const {
  const auto [i, j, k] = node_index(id);
  int n = 0;
  for (int ck = std::max(k - 1, 0); ck <= std::min(k, nz - 1); ++ck) {
    for (int cj = std::max(j - 1, 0); cj <= std::min(j, ny - 1); ++cj) {
      for (int ci = std::max(i - 1, 0); ci <= std::min(i, nx - 1); ++ci) {
        // The node is corner c of this cell; tet `local` contains corner c if it lists it.
        const int c = (i - ci) | ((j - cj) << 1) | ((k - ck) << 2);
        for (int local = 0; local < 6; ++local) {
          const auto& t = kCellTets[static_cast<std::size_t>(local)];
          if (std::find(t.begin(), t.end(), c) != t.end())
            (*out)[static_cast<std::size_t>(n++)] = 6 * cell_id(ci, cj, ck) + local;
        }
      }
    }
  }
  return n;
}

Mesh make_box_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& size, int nx, int ny,
                   int nz) {
  const TetGrid grid{origin, size, nx, ny, nz};
  RawMesh raw;
  raw.source = "box mesh";
  raw.xyz.reserve(3 * static_cast<std::size_t>(grid.num_nodes()));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const Eigen::Vector3d p = grid.node(i, j, k);
        raw.xyz.insert(raw.xyz.end(), {p.x(), p.y(), p.z()});
        const int n = grid.node_id(i, j, k);
        if (i == 0) raw.add_to_group("xmin", &n, 1);
        if (i == nx) raw.add_to_group("xmax", &n, 1);
        if (j == 0) raw.add_to_group("ymin", &n, 1);
        if (j == ny) raw.add_to_group("ymax", &n, 1);
        if (k == 0) raw.add_to_group("zmin", &n, 1);
        if (k == nz) raw.add_to_group("zmax", &n, 1);
      }
  raw.tets.reserve(static_cast<std::size_t>(grid.num_tets()));
  for (int t = 0; t < grid.num_tets(); ++t) raw.tets.push_back(grid.tet(t));
  return validate_mesh(std::move(raw), nullptr);
}

}  // namespace hapstate
