// Writes the test cube in every supported format, reads it back and compares nodes, tets,
// surface and groups.
#include "cube_writers.h"
#include "mesh/load.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

using test::CubeMesh;

// Loads `path` and checks it against the cube: same nodes (file order), same tets, a clean
// report, 12 outward boundary faces.
Mesh load_cube(const std::filesystem::path& path, const std::string& format, double tol = 1e-15) {
  const CubeMesh cube;
  MeshReport report;
  Mesh m = load_mesh(path, &report);
  EXPECT_EQ(report.format, format);
  EXPECT_EQ(report.reoriented + report.degenerate + report.duplicate + report.unreferenced, 0);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  EXPECT_EQ(m.num_nodes(), 8);
  EXPECT_EQ(m.num_tets(), 6);
  for (int i = 0; i < std::min(8, m.num_nodes()); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.nodes(k, i), cube.nodes[i][k], tol) << "node " << i;
  }
  for (int t = 0; t < std::min(6, m.num_tets()); ++t) {
    for (int k = 0; k < 4; ++k) EXPECT_EQ(m.tets(k, t), cube.tets[t][k]) << "tet " << t;
  }
  EXPECT_EQ(m.surface.cols(), 12);
  EXPECT_NEAR(test::tet_volume_sum(m), 1.0, 1e-12);
  test::expect_valid(m);
  return m;
}

void expect_group(const Mesh& m, const std::string& name, const std::vector<int>& nodes) {
  ASSERT_EQ(m.groups.count(name), 1u) << "missing group " << name;
  EXPECT_EQ(m.groups.at(name), nodes) << "group " << name;
}

TEST(RoundTrip, Msh1) {
  const Mesh m = load_cube(test::write_file("cube1.msh", test::msh1(CubeMesh())), "gmsh-1");
  EXPECT_EQ(m.groups.size(), 2u);
  expect_group(m, "7", test::bottom_nodes());
  expect_group(m, "9", test::all_cube_nodes());
}

TEST(RoundTrip, Msh22Ascii) {
  const Mesh m =
      load_cube(test::write_file("cube22.msh", test::msh2(CubeMesh(), false)), "gmsh-2.2");
  EXPECT_EQ(m.groups.size(), 2u);
  expect_group(m, "bottom", test::bottom_nodes());
  expect_group(m, "body", test::all_cube_nodes());
}

TEST(RoundTrip, Msh22Binary) {
  const Mesh m =
      load_cube(test::write_file("cube22b.msh", test::msh2(CubeMesh(), true)), "gmsh-2.2-binary");
  expect_group(m, "bottom", test::bottom_nodes());
  expect_group(m, "body", test::all_cube_nodes());
}

TEST(RoundTrip, Msh41Ascii) {
  const Mesh m =
      load_cube(test::write_file("cube41.msh", test::msh4(CubeMesh(), false)), "gmsh-4.1");
  EXPECT_EQ(m.groups.size(), 2u);
  expect_group(m, "bottom", test::bottom_nodes());
  expect_group(m, "body", test::all_cube_nodes());
}

TEST(RoundTrip, Msh41Binary) {
  const Mesh m =
      load_cube(test::write_file("cube41b.msh", test::msh4(CubeMesh(), true)), "gmsh-4.1-binary");
  expect_group(m, "bottom", test::bottom_nodes());
  expect_group(m, "body", test::all_cube_nodes());
}

TEST(RoundTrip, Msh41UnnamedPhysicalUsesNumber) {
  std::string text = test::msh4(CubeMesh(), false);
  const std::size_t a = text.find("$PhysicalNames");
  const std::size_t b =
      text.find("$EndPhysicalNames\n") + std::string("$EndPhysicalNames\n").size();
  text.erase(a, b - a);
  const Mesh m = load_cube(test::write_file("cube41n.msh", text), "gmsh-4.1");
  expect_group(m, "7", test::bottom_nodes());
  expect_group(m, "9", test::all_cube_nodes());
}

class VtkLegacy : public ::testing::TestWithParam<std::pair<bool, bool>> {};  // (binary, offsets)

TEST_P(VtkLegacy, RoundTrip) {
  const auto [binary, offsets] = GetParam();
  const std::string name =
      std::string("cube_") + (binary ? "bin" : "ascii") + (offsets ? "51" : "") + ".vtk";
  const Mesh m = load_cube(test::write_file(name, test::vtk_legacy(CubeMesh(), binary, offsets)),
                           binary ? "vtk-legacy-binary" : "vtk-legacy");
  EXPECT_EQ(m.groups.size(), 4u);
  expect_group(m, "label:1", test::all_cube_nodes());
  expect_group(m, "label:2", test::bottom_nodes());
  // zone: cells 0..2 -> 4, cells 3..7 -> 5 (tets 3..5 and both triangles).
  const CubeMesh cube;
  std::set<int> zone4;
  for (int t = 0; t < 3; ++t) zone4.insert(cube.tets[t].begin(), cube.tets[t].end());
  expect_group(m, "zone:4", std::vector<int>(zone4.begin(), zone4.end()));
  EXPECT_EQ(m.groups.count("quality:0"), 0u);  // float arrays are not groups
}

INSTANTIATE_TEST_SUITE_P(Layouts, VtkLegacy,
                         ::testing::Values(std::pair{false, false}, std::pair{false, true},
                                           std::pair{true, false}, std::pair{true, true}));

class Vtu : public ::testing::TestWithParam<test::VtuMode> {};

TEST_P(Vtu, RoundTrip) {
  const Mesh m = load_cube(test::write_file("cube" + std::to_string(int(GetParam())) + ".vtu",
                                            test::vtu(CubeMesh(), GetParam())),
                           "vtu");
  EXPECT_EQ(m.groups.size(), 2u);
  expect_group(m, "label:1", test::all_cube_nodes());
  expect_group(m, "label:2", test::bottom_nodes());
}

INSTANTIATE_TEST_SUITE_P(Encodings, Vtu,
                         ::testing::Values(test::VtuMode::kAscii, test::VtuMode::kBase64,
                                           test::VtuMode::kBase64UInt64,
                                           test::VtuMode::kAppendedRaw,
                                           test::VtuMode::kAppendedBase64, test::VtuMode::kZlib));

TEST(RoundTrip, VtuUnderVtkExtension) {
  // Some tools (e.g. SOFA's Bunny.vtk) write VTK XML under a .vtk name.
  load_cube(test::write_file("cube_xml.vtk", test::vtu(CubeMesh(), test::VtuMode::kAscii)), "vtu");
}

TEST(RoundTrip, Medit) {
  const Mesh m = load_cube(test::write_file("cube.mesh", test::medit(CubeMesh())), "medit");
  EXPECT_EQ(m.groups.size(), 2u);
  expect_group(m, "ref:7", test::bottom_nodes());
  expect_group(m, "ref:9", test::all_cube_nodes());
}

class TetGen : public ::testing::TestWithParam<int> {};  // index base

TEST_P(TetGen, RoundTripGivenEitherFile) {
  const int base = GetParam();
  const auto [node, ele] = test::tetgen(CubeMesh(), base);
  const std::string stem = "cube_tetgen" + std::to_string(base);
  const auto node_path = test::write_file(stem + ".node", node);
  const auto ele_path = test::write_file(stem + ".ele", ele);
  for (const auto& path : {node_path, ele_path}) {
    const Mesh m = load_cube(path, "tetgen");
    EXPECT_EQ(m.groups.size(), 2u);
    expect_group(m, "marker:5", test::bottom_nodes());
    expect_group(m, "region:3", test::all_cube_nodes());
  }
}

INSTANTIATE_TEST_SUITE_P(Bases, TetGen, ::testing::Values(0, 1));

}  // namespace
}  // namespace hapstate
