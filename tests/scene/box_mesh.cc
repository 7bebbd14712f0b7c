#include "box_mesh.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <map>
#include <vector>

namespace hapstate::testing {

namespace {

Triangles boundary_faces(const Mesh& mesh) {
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;
  constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};  // outward
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (const auto& f : kFace) {
      std::array<int, 3> oriented{mesh.tets(f[0], t), mesh.tets(f[1], t), mesh.tets(f[2], t)};
      std::array<int, 3> key = oriented;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      ++entry.first;
      entry.second = oriented;
    }
  }
  std::vector<std::array<int, 3>> once;
  for (const auto& [key, entry] : faces) {
    if (entry.first == 1) once.push_back(entry.second);
  }
  Triangles surface(3, static_cast<Eigen::Index>(once.size()));
  for (size_t i = 0; i < once.size(); ++i) {
    for (int r = 0; r < 3; ++r)
      surface(r, static_cast<Eigen::Index>(i)) = once[i][static_cast<size_t>(r)];
  }
  return surface;
}

}  // namespace

Mesh make_box_mesh(int nx, int ny, int nz, double h, const Eigen::Vector3d& offset) {
  Mesh mesh;
  mesh.nodes.resize(3, nx * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        mesh.nodes.col(box_node(i, j, k, nx, ny)) = offset + h * Eigen::Vector3d(i, j, k);
  std::vector<std::array<int, 4>> tets;
  std::array<int, 3> axes{0, 1, 2};
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        std::sort(axes.begin(), axes.end());
        do {  // path 000 -> e_a -> e_a + e_b -> 111 for each permutation (a, b, c)
          std::array<int, 3> c{i, j, k};
          std::array<int, 4> tet{};
          tet[0] = box_node(c[0], c[1], c[2], nx, ny);
          for (int s = 0; s < 3; ++s) {
            ++c[static_cast<size_t>(axes[static_cast<size_t>(s)])];
            tet[static_cast<size_t>(s + 1)] = box_node(c[0], c[1], c[2], nx, ny);
          }
          Eigen::Matrix3d edges;
          for (int s = 0; s < 3; ++s)
            edges.col(s) = mesh.nodes.col(tet[static_cast<size_t>(s + 1)]) - mesh.nodes.col(tet[0]);
          if (edges.determinant() < 0) std::swap(tet[2], tet[3]);
          tets.push_back(tet);
        } while (std::next_permutation(axes.begin(), axes.end()));
      }
  mesh.tets.resize(4, static_cast<Eigen::Index>(tets.size()));
  for (size_t t = 0; t < tets.size(); ++t)
    for (int r = 0; r < 4; ++r)
      mesh.tets(r, static_cast<Eigen::Index>(t)) = tets[t][static_cast<size_t>(r)];
  mesh.surface = boundary_faces(mesh);
  return mesh;
}

Mesh merge_meshes(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.nodes.resize(3, a.num_nodes() + b.num_nodes());
  m.nodes << a.nodes, b.nodes;
  m.tets.resize(4, a.num_tets() + b.num_tets());
  m.tets << a.tets, (b.tets.array() + a.num_nodes()).matrix();
  m.surface.resize(3, a.surface.cols() + b.surface.cols());
  m.surface << a.surface, (b.surface.array() + a.num_nodes()).matrix();
  return m;
}

}  // namespace hapstate::testing
