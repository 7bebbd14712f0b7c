// Closed triangle surfaces (OBJ, STL) are filled with tets by Gmsh; open surfaces give clear
// errors (self-intersecting ones are carved: carve_test.cc).
#include "cube_writers.h"
#include "mesh/load.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace hapstate {
namespace {

struct Surface {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> faces;

  double volume() const {
    double v = 0;
    for (const auto& f : faces) v += points[f[0]].dot(points[f[1]].cross(points[f[2]])) / 6.0;
    return v;
  }
  double area() const {
    double a = 0;
    for (const auto& f : faces)
      a += 0.5 * (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]).norm();
    return a;
  }
};

// Icosahedron subdivided `levels` times, projected on the unit sphere; faces outward.
Surface icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Surface s;
  for (const auto& p : std::vector<Eigen::Vector3d>{{-1, t, 0},
                                                    {1, t, 0},
                                                    {-1, -t, 0},
                                                    {1, -t, 0},
                                                    {0, -1, t},
                                                    {0, 1, t},
                                                    {0, -1, -t},
                                                    {0, 1, -t},
                                                    {t, 0, -1},
                                                    {t, 0, 1},
                                                    {-t, 0, -1},
                                                    {-t, 0, 1}}) {
    s.points.push_back(p.normalized());
  }
  s.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      s.points.push_back((s.points[a] + s.points[b]).normalized());
      return mid[key] = static_cast<int>(s.points.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& f : s.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    s.faces = next;
  }
  return s;
}

Surface cube_surface() {
  Surface s;
  for (const auto& p : test::CubeMesh().nodes) s.points.emplace_back(p[0], p[1], p[2]);
  s.faces = test::cube_surface();
  return s;
}

std::string obj_text(const Surface& s) {
  std::ostringstream o;
  o.precision(17);
  o << "# test surface\nmtllib none.mtl\no shape\n";
  for (const auto& p : s.points) o << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  o << "vn 0 0 1\ns off\n";
  for (const auto& f : s.faces)
    o << "f " << f[0] + 1 << "//1 " << f[1] + 1 << "//1 " << f[2] + 1 << "//1\n";
  return o.str();
}

std::string stl_ascii(const Surface& s) {
  std::ostringstream o;
  o.precision(9);
  o << "solid test\n";
  for (const auto& f : s.faces) {
    o << " facet normal 0 0 0\n  outer loop\n";
    for (int v : f)
      o << "   vertex " << float(s.points[v].x()) << " " << float(s.points[v].y()) << " "
        << float(s.points[v].z()) << "\n";
    o << "  endloop\n endfacet\n";
  }
  o << "endsolid test\n";
  return o.str();
}

std::string stl_binary(const Surface& s) {
  std::string b(80, ' ');
  b.replace(0, 5, "solid");  // binary files may start with "solid" too
  test::put<std::uint32_t>(&b, static_cast<std::uint32_t>(s.faces.size()));
  for (const auto& f : s.faces) {
    for (int k = 0; k < 3; ++k) test::put<float>(&b, 0.0f);
    for (int v : f) {
      for (int k = 0; k < 3; ++k) test::put<float>(&b, static_cast<float>(s.points[v][k]));
    }
    test::put<std::uint16_t>(&b, 0);
  }
  return b;
}

// The tet mesh fills the surface: its boundary is the input surface (same face count, area and
// enclosed volume), tets positive.
void expect_filled(const Mesh& m, const Surface& s, double tol) {
  test::expect_valid(m);
  EXPECT_EQ(m.surface.cols(), static_cast<int>(s.faces.size()));
  EXPECT_NEAR(test::tet_volume_sum(m), s.volume(), tol);
  double area = 0;
  for (int f = 0; f < m.surface.cols(); ++f) {
    area += 0.5 * (m.nodes.col(m.surface(1, f)) - m.nodes.col(m.surface(0, f)))
                      .cross(m.nodes.col(m.surface(2, f)) - m.nodes.col(m.surface(0, f)))
                      .norm();
  }
  EXPECT_NEAR(area, s.area(), tol);
}

TEST(Surface, CubeObjIsFilled) {
  const Surface s = cube_surface();
  MeshReport report;
  const Mesh m = load_mesh(test::write_file("cube_surface.obj", obj_text(s)), &report);
  EXPECT_EQ(report.format, "obj-surface");
  EXPECT_NEAR(s.volume(), 1.0, 1e-15);
  expect_filled(m, s, 1e-12);
}

TEST(Surface, SphereObjAndStlAreFilled) {
  const Surface s = icosphere(2);  // 320 faces, volume ~4.07 (inscribed in the unit sphere)
  ASSERT_EQ(s.faces.size(), 320u);
  const Mesh from_obj = load_mesh(test::write_file("sphere.obj", obj_text(s)));
  expect_filled(from_obj, s, 1e-12);
  EXPECT_GT(from_obj.num_tets(), 320 / 3);
  // STL stores float32 coordinates: compare with a float-sized tolerance.
  MeshReport report;
  const Mesh from_stl = load_mesh(test::write_file("sphere.stl", stl_ascii(s)), &report);
  EXPECT_EQ(report.format, "stl-surface");
  EXPECT_EQ(from_stl.num_nodes() >= 162, true);  // 162 surface vertices merged from 960 corners
  expect_filled(from_stl, s, 1e-5);
  const Mesh from_binary = load_mesh(test::write_file("sphere_bin.stl", stl_binary(s)));
  expect_filled(from_binary, s, 1e-5);
}

TEST(Surface, OpenSurfaceIsAnError) {
  Surface s = cube_surface();
  s.faces.pop_back();  // remove one triangle of the x = 1 face
  const auto path = test::write_file("open.obj", obj_text(s));
  try {
    load_mesh(path);
    FAIL() << "open surface accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("open surface"), std::string::npos) << msg;
    EXPECT_NE(msg.find("open.obj:"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace hapstate
