// The contact probe's view for the state space on the block of tests/solver/contact_problems.h
// (nodes every 0.5 on [0, 4]^2 x [0, 1], base z = 0 fixed, sphere radius 0.8): which probe
// positions leave the body at rest, and which moves between them sweep past every node; the
// expected answers are worked out by hand from the node lattice.
#include "statespace/probe_model.h"
#include "../solver/contact_problems.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

TEST(ContactProbeModel, ZeroConfigurationWhereTheSphereTouchesNoSurfaceNode) {
  const Problem p = testing::block_problem();
  const auto probe = make_probe_model(p);
  EXPECT_TRUE(probe->clear_of_body(p.probe_rest));
  EXPECT_TRUE(probe->holds_zero_configuration(p.probe_rest));
  // Above the top-face node (2, 2, 1): 0.85 away is clear, 0.75 away touches.
  EXPECT_TRUE(probe->holds_zero_configuration(Eigen::Vector3d(2, 2, 1.85)));
  EXPECT_FALSE(probe->holds_zero_configuration(Eigen::Vector3d(2, 2, 1.75)));
  EXPECT_FALSE(probe->clear_of_body(Eigen::Vector3d(2, 2, 1.75)));
  // Beside the fixed base (z = 0 nodes are not candidates): only the z = 0.5 nodes count.
  EXPECT_TRUE(
      probe->holds_zero_configuration(Eigen::Vector3d(-0.6, 2, -0.5)));  // 0.78 from (0, 2, 0)
  EXPECT_FALSE(
      probe->holds_zero_configuration(Eigen::Vector3d(-0.6, 2, 0.1)));  // 0.72 from (0, 2, 0.5)
}

TEST(ContactProbeModel, MoveIsTrivialOnlyIfTheSphereSweepsPastEveryNode) {
  const Problem p = testing::block_problem();
  const auto probe = make_probe_model(p);
  // At x = -0.78, z = 0.5 the sphere reaches a node (0, y_n, 0.5) iff |y - y_n| < 0.178; the
  // nodes are at y = 0, 0.5, 1, ...: y = 0.25 and 0.75 are clear, the segment between them
  // passes y = 0.5.
  const Eigen::Vector3d a(-0.78, 0.25, 0.5), b(-0.78, 0.75, 0.5), c(-0.98, 0.25, 0.5);
  ASSERT_TRUE(probe->holds_zero_configuration(a));
  ASSERT_TRUE(probe->holds_zero_configuration(b));
  EXPECT_FALSE(probe->trivial_move(a, b));
  EXPECT_FALSE(probe->trivial_move(b, a));
  EXPECT_TRUE(probe->trivial_move(a, c));  // straight away from the face
  EXPECT_TRUE(probe->trivial_move(a, a));
  EXPECT_FALSE(probe->trivial_move(a, Eigen::Vector3d(-0.7, 0.25, 0.5)));  // target touches
}

// A sphere whose centre is inside the rest body farther than its radius from the surface touches
// no triangle (node) either, but it is not clear of the body: only pushing gets it there (a
// check-point there is a workspace one, reached by expansion, never a free one with the zero
// configuration), and no move into or out of it is trivial. Both models, on the block with a
// sphere of radius 0.2 at mid-height (0.5 from the top face and from the base).
TEST(ContactProbeModel, CentreDeepInsideTheBodyIsNotClear) {
  for (Friction friction : {Friction::kStick, Friction::kNone}) {
    Problem p = testing::block_problem(8, friction);
    p.contact->radius = 0.2;
    const auto probe = make_probe_model(p);
    const Eigen::Vector3d inside(2.1, 2.2, 0.5), also_inside(2.6, 2.2, 0.5);
    const Eigen::Vector3d above(2.1, 2.2, 1.5);  // 0.5 above the top face
    EXPECT_FALSE(probe->clear_of_body(inside)) << int(friction);
    EXPECT_FALSE(probe->holds_zero_configuration(inside)) << int(friction);
    EXPECT_FALSE(probe->trivial_move(inside, also_inside)) << int(friction);
    EXPECT_FALSE(probe->trivial_move(above, inside)) << int(friction);
    EXPECT_TRUE(probe->clear_of_body(above)) << int(friction);
    EXPECT_TRUE(probe->trivial_move(above, Eigen::Vector3d(2.6, 2.2, 1.5))) << int(friction);
  }
}

// The clearance the playback file stores (docs/playback.md, "Contact onset"): the signed
// distance of the centre from the rest surface minus the radius, negative and decreasing with
// depth once the centre is inside the block, continuous through the surface.
TEST(ContactProbeModel, ClearanceIsTheSignedDistanceMinusTheRadius) {
  const Problem p = testing::block_problem(8, Friction::kNone);
  const auto probe = make_probe_model(p);
  auto clearance = [&](double x, double y, double z) {
    return probe->clearance(Eigen::Vector3d(x, y, z), 1.0).value();
  };
  const auto above = clearance(2.1, 2.2, 1.5);  // 0.5 above the top face z = 1
  EXPECT_NEAR(above.gap, 0.5 - 0.8, 1e-12);
  EXPECT_NEAR((above.gradient - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
  const auto inside = clearance(2.1, 2.2, 0.7);  // 0.3 below it, inside the block
  EXPECT_NEAR(inside.gap, -0.3 - 0.8, 1e-12);
  EXPECT_NEAR((inside.gradient - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(clearance(2.1, 2.2, 1.0 + 1e-9).gap, clearance(2.1, 2.2, 1.0 - 1e-9).gap, 1e-8);
  const auto beside = clearance(-0.4, 2.2, 0.6);  // 0.4 beside the face x = 0
  EXPECT_NEAR(beside.gap, 0.4 - 0.8, 1e-12);
  EXPECT_NEAR((beside.gradient - Eigen::Vector3d(-1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(clearance(2.0, 2.0, 4.0).gap, 1.0);  // nothing within the range: the range
  // Sticking: from the nearest candidate node, (2, 2, 1) here.
  const Problem stick = testing::block_problem();
  const auto node = make_probe_model(stick)->clearance(Eigen::Vector3d(2, 2, 1.85), 1.0).value();
  EXPECT_NEAR(node.gap, 0.85 - 0.8 * (1.0 - kPenetrationTolerance), 1e-12);
}

TEST(GrabProbeModel, NoTrivialMovesAndZeroOnlyAtRest) {
  Problem p = testing::block_problem();
  p.contact.reset();
  p.constraints.probe_nodes = {p.mesh.num_nodes() - 1};
  for (int c = 0; c < 3; ++c)
    p.constraints.role[3 * (p.mesh.num_nodes() - 1) + c] = DofRole::kProbe;
  p.probe_rest = p.mesh.nodes.col(p.mesh.num_nodes() - 1);
  const auto probe = make_probe_model(p);
  EXPECT_FALSE(probe->clear_of_body(p.probe_rest));  // the grabbed node is never clear
  EXPECT_TRUE(probe->holds_zero_configuration(p.probe_rest));
  EXPECT_FALSE(probe->holds_zero_configuration(p.probe_rest + Eigen::Vector3d(0, 0, 0.1)));
  EXPECT_FALSE(probe->trivial_move(p.probe_rest, p.probe_rest));
  EXPECT_FALSE(probe->clearance(p.probe_rest, 1.0).has_value());
}

}  // namespace
}  // namespace hapstate
