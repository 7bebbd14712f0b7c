// The real meshes in data/meshes import with the counts and volumes of their READMEs
// (data/meshes/README.md; boundary counts from the shared mesh notes).
#include "mesh/load.h"
#include "mesh_test_util.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

struct Expected {
  const char* file;
  int nodes;
  int tets;
  int boundary_nodes;  // -1: not documented
  int boundary_faces;
  double volume;  // -1: not documented
  const char* format;
};

class BundledMesh : public ::testing::TestWithParam<Expected> {};

TEST_P(BundledMesh, ImportsWithDocumentedCounts) {
  const Expected& e = GetParam();
  MeshReport report;
  const Mesh m = load_mesh(std::string(HAPSTATE_TEST_DATA) + "/meshes/" + e.file, &report);
  EXPECT_EQ(report.format, e.format);
  EXPECT_EQ(m.num_nodes(), e.nodes);
  EXPECT_EQ(m.num_tets(), e.tets);
  if (e.boundary_faces >= 0) {
    EXPECT_EQ(test::boundary_node_count(m), e.boundary_nodes);
    EXPECT_EQ(m.surface.cols(), e.boundary_faces);
  }
  if (e.volume > 0) {
    EXPECT_NEAR(test::tet_volume_sum(m), e.volume, 0.01);
  }
  EXPECT_EQ(report.reoriented, 0);
  EXPECT_EQ(report.degenerate, 0);
  EXPECT_EQ(report.duplicate, 0);
  EXPECT_EQ(report.unreferenced, 0);
  test::expect_valid(m);
  // Euler characteristic of the boundary: one sphere-like shell.
  EXPECT_EQ(test::boundary_node_count(m) - 3 * m.surface.cols() / 2 + m.surface.cols(), 2);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, BundledMesh,
    ::testing::Values(Expected{"liver.msh", 181, 596, 140, 276, 36.56, "gmsh-1"},
                      Expected{"liverFine.vtu", 4293, 22019, 1603, 3202, 38.96, "vtu"},
                      Expected{"bunny.msh", 4670, 19379, 3135, 6266, 6.010, "gmsh-4.1"},
                      Expected{"liverCoarse.vtu", 357, 1369, -1, -1, -1, "vtu"},
                      Expected{"liverSemiFine.vtu", 1375, 6444, -1, -1, -1, "vtu"}),
    [](const auto& info) {
      std::string name = info.param.file;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST(BundledMesh, LiverMshPhysicalGroupHoldsEveryNode) {
  // liver.msh tags every tet with physical region 1 (no $PhysicalNames in format 1).
  const Mesh m = load_mesh(std::string(HAPSTATE_TEST_DATA) + "/meshes/liver.msh");
  ASSERT_EQ(m.groups.size(), 1u);
  ASSERT_EQ(m.groups.count("1"), 1u);
  EXPECT_EQ(m.groups.at("1").size(), 181u);
  EXPECT_EQ(m.groups.at("1").front(), 0);
  EXPECT_EQ(m.groups.at("1").back(), 180);
  // File node 1 is -0.979259 2.23512 2.61245 and becomes node 0.
  EXPECT_NEAR(m.nodes(0, 0), -0.979259, 1e-12);
  EXPECT_NEAR(m.nodes(2, 0), 2.61245, 1e-12);
}

TEST(BundledMesh, BunnyHasNoGroups) {
  // Entity tag 0 and no $Entities: no physical groups.
  const Mesh m = load_mesh(std::string(HAPSTATE_TEST_DATA) + "/meshes/bunny.msh");
  EXPECT_TRUE(m.groups.empty());
}

}  // namespace
}  // namespace hapstate
