// Test helper: a structured tet mesh of an axis-aligned box, and a problem around it.
#pragma once

#include "scene/problem.h"

#include <Eigen/Dense>

#include <array>
#include <utility>

namespace hapstate::testing {

// Box [0, size] with cells[0] x cells[1] x cells[2] hexahedra, each split into 6 tets around its
// (min -> max) diagonal, so neighbouring cells share faces. Every tet positively oriented.
inline Mesh box_mesh(const Eigen::Vector3d& size, const std::array<int, 3>& cells) {
  const int nx = cells[0] + 1, ny = cells[1] + 1, nz = cells[2] + 1;
  auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  Mesh m;
  m.nodes.resize(3, nx * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.nodes.col(id(i, j, k)) = Eigen::Vector3d(size.x() * i / cells[0],
                                                   size.y() * j / cells[1],
                                                   size.z() * k / cells[2]);
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                                 {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  m.tets.resize(4, 6 * cells[0] * cells[1] * cells[2]);
  int e = 0;
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c{i, j, k};
          m.tets(0, e) = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            m.tets(s + 1, e) = id(c[0], c[1], c[2]);
          }
          Eigen::Matrix3d d;
          for (int s = 0; s < 3; ++s)
            d.col(s) = m.nodes.col(m.tets(s + 1, e)) - m.nodes.col(m.tets(0, e));
          if (d.determinant() < 0) std::swap(m.tets(2, e), m.tets(3, e));
          ++e;
        }
  m.source = "box_mesh (test)";
  return m;
}

}  // namespace hapstate::testing
