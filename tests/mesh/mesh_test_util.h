// Helpers for the mesh tests: a small reference mesh (unit cube, 6 tets, one boundary group),
// temporary files, binary packing and geometric checks of a loaded Mesh.
#pragma once

#include "mesh/mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <unistd.h>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace hapstate::test {

// Unit cube [0,1]^3: node v at (v&1, v>>1&1, v>>2&1), 6 positively oriented tets around the
// diagonal 0-7, and the two triangles of the face z = 0 (the "bottom" group: nodes 0..3).
struct CubeMesh {
  std::vector<std::array<double, 3>> nodes;
  std::vector<std::array<int, 4>> tets;
  std::vector<std::array<int, 3>> bottom;  // triangles on z = 0

  CubeMesh() {
    for (int v = 0; v < 8; ++v)
      nodes.push_back({double(v & 1), double((v >> 1) & 1), double((v >> 2) & 1)});
    const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& a : axes) {
      std::array<int, 4> t{0, 1 << a[0], (1 << a[0]) | (1 << a[1]), 7};
      if (det(t) < 0) std::swap(t[2], t[3]);
      tets.push_back(t);
    }
    bottom = {{0, 2, 1}, {1, 2, 3}};
  }
  double det(const std::array<int, 4>& t) const {
    Eigen::Matrix3d e;
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) e(j, k) = nodes[t[k + 1]][j] - nodes[t[0]][j];
    }
    return e.determinant();
  }
};

inline std::vector<int> bottom_nodes() { return {0, 1, 2, 3}; }
inline std::vector<int> all_cube_nodes() { return {0, 1, 2, 3, 4, 5, 6, 7}; }

// A fresh temporary directory for this test process.
inline std::filesystem::path temp_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("hapstate_mesh_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                      ("hapstate_mesh_test_" + std::to_string(::getpid())),
                                  ignored);
    });
    return d;
  }();
  return dir;
}

inline std::filesystem::path write_file(const std::string& name, const std::string& content) {
  const auto path = temp_dir() / name;
  std::ofstream out(path, std::ios::binary);
  out << content;
  return path;
}

// Appends the bytes of `v` in little- or big-endian order.
template <class T>
void put(std::string* out, T v, bool big_endian = false) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  if (big_endian) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  out->append(bytes, sizeof(T));
}

inline std::string base64(const std::string& bytes) {
  static const char* kChars = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out += kChars[(v >> 18) & 63];
    out += kChars[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kChars[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kChars[v & 63] : '=';
  }
  return out;
}

inline double signed_volume(const Mesh& m, int t) {
  const Eigen::Vector3d a = m.nodes.col(m.tets(0, t));
  Eigen::Matrix3d e;
  e << m.nodes.col(m.tets(1, t)) - a, m.nodes.col(m.tets(2, t)) - a, m.nodes.col(m.tets(3, t)) - a;
  return e.determinant() / 6.0;
}

inline double tet_volume_sum(const Mesh& m) {
  double v = 0;
  for (int t = 0; t < m.num_tets(); ++t) v += signed_volume(m, t);
  return v;
}

// Volume enclosed by the surface (divergence theorem); positive for outward faces.
inline double enclosed_volume(const Mesh& m) {
  double v = 0;
  for (int f = 0; f < m.surface.cols(); ++f) {
    v += m.nodes.col(m.surface(0, f))
             .dot(m.nodes.col(m.surface(1, f)).cross(m.nodes.col(m.surface(2, f)))) /
         6.0;
  }
  return v;
}

inline int boundary_node_count(const Mesh& m) {
  std::set<int> nodes(m.surface.data(), m.surface.data() + m.surface.size());
  return static_cast<int>(nodes.size());
}

// Every tet positive, surface closed (each directed edge once with its reverse present) and
// outward (enclosed volume == tet volume sum).
inline void expect_valid(const Mesh& m) {
  for (int t = 0; t < m.num_tets(); ++t) ASSERT_GT(signed_volume(m, t), 0.0) << "tet " << t;
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < m.surface.cols(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{m.surface(k, f), m.surface((k + 1) % 3, f)}];
  }
  for (const auto& [e, n] : directed) {
    ASSERT_EQ(n, 1) << "edge " << e.first << "-" << e.second << " used twice in one direction";
    ASSERT_EQ(directed.count({e.second, e.first}), 1u)
        << "open edge " << e.first << "-" << e.second;
  }
  const double vol = tet_volume_sum(m);
  EXPECT_NEAR(enclosed_volume(m), vol, 1e-9 * std::abs(vol));
}

}  // namespace hapstate::test
