// The bundled default scene, pipelines/liver/scene.toml. The Parse test needs only the scene
// module; BuildProblem reads data/meshes/liver.msh through load_mesh (mesh module), so it
// depends on the mesh reader being in place.
#include "scene/bind.h"
#include "scene/select.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace hapstate {
namespace {

const std::filesystem::path kScene =
    std::filesystem::path(HAPSTATE_SOURCE_DIR) / "pipelines" / "liver" / "scene.toml";

TEST(LiverScene, Parses) {
  const Scene s = load_scene(kScene);
  EXPECT_EQ(
      s.mesh.file,
      (std::filesystem::path(HAPSTATE_SOURCE_DIR) / "data/meshes/liver.msh").lexically_normal());
  EXPECT_EQ(s.mesh.unit, 0.01);
  EXPECT_EQ(s.material.law, Law::kNeoHooke);
  EXPECT_EQ(s.material.young, 5000.0);
  EXPECT_EQ(s.material.poisson, 0.45);
  ASSERT_EQ(s.fixed.size(), 1u);
  const auto& box = std::get<BoxSelector>(s.fixed[0].where).box;
  EXPECT_EQ(box.min, Eigen::Vector3d(0, 3, -1));
  EXPECT_EQ(box.max, Eigen::Vector3d(2, 5, 2));
  EXPECT_EQ(s.probe.mode, ProbeMode::kGrab);
  EXPECT_EQ(s.probe.point, Eigen::Vector3d(-2.5, 3.5, 2.2));
  EXPECT_FALSE(s.probe.radius);
  EXPECT_EQ(s.probe.max_force, 3.0);
  EXPECT_EQ(s.grid.spacing, Eigen::Vector3d::Constant(0.5));
  ASSERT_TRUE(s.grid.box);  // 1.5 cm (3 spacings) each way around the grabbed node
  EXPECT_NEAR(s.grid.box->max.x() - s.grid.box->min.x(), 3.02, 1e-12);
  EXPECT_EQ(s.solver.substeps, 4);
  EXPECT_EQ(s.solver.tolerance, 1e-8);
  EXPECT_EQ(s.solver.max_iterations, 30);
}

// Needs load_mesh (mesh module) to read the Gmsh 1 liver mesh.
TEST(LiverScene, BuildProblem) {
  const Problem p = build_problem(load_scene(kScene));
  ASSERT_EQ(p.mesh.num_nodes(), 181);
  ASSERT_EQ(p.mesh.num_tets(), 596);
  EXPECT_EQ(p.unit, 0.01);
  // SOFA's fixture box holds 18 nodes, all three components each.
  int fixed = 0;
  for (int n = 0; n < 181; ++n) {
    const int count =
        static_cast<int>(std::count(p.constraints.role.begin() + 3 * n,
                                    p.constraints.role.begin() + 3 * n + 3, DofRole::kFixed));
    EXPECT_TRUE(count == 0 || count == 3) << "node " << n;
    if (count == 3) {
      ++fixed;
      EXPECT_GE(p.mesh.nodes(0, n), 0.0);
      EXPECT_LE(p.mesh.nodes(0, n), 2.0);
    }
  }
  EXPECT_EQ(fixed, 18);
  // The grabbed node: node 100 (0-based), on the surface of the far lobe, far from the fixture.
  ASSERT_EQ(p.constraints.probe_nodes, std::vector<int>{100});
  const std::vector<int> surface = surface_nodes(p.mesh);
  EXPECT_TRUE(std::binary_search(surface.begin(), surface.end(), 100));
  EXPECT_TRUE(p.probe_rest.isApprox(Eigen::Vector3d(-2.51058, 3.4868, 2.21873),
                                    1e-12))  // liver.msh node "101"
      << p.probe_rest.transpose();
  EXPECT_LT(p.probe_rest.x(), -2.0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(p.constraints.role[300 + c], DofRole::kProbe);
  // neohooke from E = 5000 Pa, nu = 0.45: c10 = mu/2, d1 = 2/K.
  EXPECT_NEAR(p.material.c10, 5000.0 / 2.9 / 2.0, 1e-9);
  EXPECT_NEAR(p.material.d1, 2.0 / (5000.0 / 0.3), 1e-15);
  EXPECT_EQ(p.max_force, 3.0);
}

// pipelines/liver-gravity: the same liver under its weight on an elastic bed. It builds, rests
// settled (its sag as docs/benchmarks.md gives it), and the grab point follows the sag.
TEST(LiverScene, UnderGravityOnItsBedSettles) {
  const Scene s = load_scene(std::filesystem::path(HAPSTATE_SOURCE_DIR) / "pipelines" /
                             "liver-gravity" / "scene.toml");
  ASSERT_TRUE(s.loads.gravity.has_value());
  ASSERT_EQ(s.supports.size(), 1u);
  const Problem p = build_problem(s);
  ASSERT_EQ(p.rest_m.size(), 3 * p.mesh.num_nodes());
  double largest = 0;
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    largest = std::max(largest, p.rest_m.segment<3>(3 * n).norm() / p.unit);
  EXPECT_NEAR(largest, 0.763, 0.001);  // cm
  EXPECT_NEAR(p.probe_sag.y(), -0.534, 0.001);
  EXPECT_EQ(p.probe_rest, p.mesh.nodes.col(p.constraints.probe_nodes[0]) + p.probe_sag);
}

}  // namespace
}  // namespace hapstate
