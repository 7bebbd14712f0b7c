// connected_components and free_rigid_modes on meshes built in code.
#include "scene/rigid_modes.h"
#include "box_mesh.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

using testing::make_box_mesh;
using testing::merge_meshes;

std::vector<DofRole> roles(int num_nodes, const std::vector<int>& fixed_nodes) {
  std::vector<DofRole> role(static_cast<size_t>(3 * num_nodes), DofRole::kFree);
  for (int n : fixed_nodes)
    for (int c = 0; c < 3; ++c) role[static_cast<size_t>(3 * n + c)] = DofRole::kFixed;
  return role;
}

TEST(ConnectedComponents, SeparatesDisjointPartsAndSkipsUnusedNodes) {
  Mesh m = merge_meshes(make_box_mesh(2, 2, 2), make_box_mesh(2, 2, 3, 1.0, {5, 0, 0}));
  m.nodes.conservativeResize(3, m.num_nodes() + 1);  // a node used by no tet
  m.nodes.col(m.num_nodes() - 1) = Eigen::Vector3d(9, 9, 9);
  const auto components = connected_components(m);
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0], (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(components[1].size(), 12u);
  EXPECT_EQ(components[1].front(), 8);
  EXPECT_EQ(components[1].back(), 19);
}

TEST(FreeRigidModes, ThreeNonCollinearNodesRemoveAllModes) {
  const Mesh m = make_box_mesh(3, 3, 3);
  EXPECT_TRUE(free_rigid_modes(m, roles(27, {0, 1, 3})).empty());
  const auto two = free_rigid_modes(m, roles(27, {0, 1}));
  ASSERT_EQ(two.size(), 1u);
  EXPECT_EQ(two[0].free_modes, 1);
  EXPECT_EQ(two[0].example, "rotation about x through (1, 0, 0)");
  const auto none = free_rigid_modes(m, roles(27, {}));
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].free_modes, 6);
  EXPECT_EQ(none[0].num_nodes, 27);
}

TEST(FreeRigidModes, ScaleDoesNotChangeTheRank) {
  // A tiny and a huge body: the rank test is relative to the component size.
  for (double h : {1e-6, 1e6}) {
    const Mesh m = make_box_mesh(3, 3, 3, h);
    EXPECT_TRUE(free_rigid_modes(m, roles(27, {0, 1, 3})).empty()) << "h = " << h;
    const auto line = free_rigid_modes(m, roles(27, {0, 1, 2}));
    ASSERT_EQ(line.size(), 1u) << "h = " << h;
    EXPECT_EQ(line[0].free_modes, 1) << "h = " << h;
  }
}

TEST(FreeRigidModes, TranslationFreeWhenOnlyOneComponentHeld) {
  const Mesh m = make_box_mesh(3, 3, 3);
  std::vector<DofRole> role(81, DofRole::kFree);
  for (int n = 0; n < 9; ++n) {  // face z = 0, x and z held: y translation free
    role[static_cast<size_t>(3 * n + 0)] = DofRole::kFixed;
    role[static_cast<size_t>(3 * n + 2)] = DofRole::kFixed;
  }
  const auto free = free_rigid_modes(m, role);
  ASSERT_EQ(free.size(), 1u);
  EXPECT_EQ(free[0].free_modes, 1);
  EXPECT_EQ(free[0].example, "translation along y");
}

}  // namespace
}  // namespace hapstate
