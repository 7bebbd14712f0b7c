// bind_scene: fixed selectors, grab variants, conflicts, material and the rigid-body check, on
// structured box meshes built in code (node (i, j, k) at (i, j, k), id i + nx (j + ny k)).
#include "box_mesh.h"
#include "scene/bind.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

using testing::box_node;
using testing::error_of;
using testing::make_box_mesh;
using testing::merge_meshes;
using testing::ScratchDir;

// Lines 1..7; the [[fixed]] tables start at line 8.
const std::string kHead =
    "[mesh]\nfile = \"box.msh\"\nunit = 0.001\n"
    "[material]\nlaw = \"stvk\"\nmu = 1000\n";
const std::string kTail = "[grid]\nspacing = 0.25\n[solver]\nsubsteps = 7\n";

class BindScene : public ::testing::Test {
 protected:
  // A scene with `fixed` ([[fixed]] tables, from line 7) and the body of [probe].
  Scene scene(const std::string& fixed, const std::string& probe) const {
    const std::string text =
        kHead + "lambda = 4000\n" + fixed + "[probe]\n" + probe + "\nmax_force = 1.5\n" + kTail;
    return parse_scene(text, scene_path(), SceneParseOptions{.check_files = false});
  }
  std::filesystem::path scene_path() const { return dir_.path() / "scene.toml"; }
  std::string at(int line, const std::string& message) const {
    return scene_path().string() + ":" + std::to_string(line) + ": " + message;
  }
  static DofRole role(const Problem& p, int node, int component) {
    return p.constraints.role[static_cast<size_t>(3 * node + component)];
  }

  ScratchDir dir_;
  Mesh cube_ = make_box_mesh(3, 3, 3);  // 27 nodes on [0, 2]^3
};

// Face x = 0: its nodes lie on the boundary of the closed box (x = 0, y = 2, z = 2 included).
const std::string kFixX0 = "[[fixed]]\nbox = [[0, 0, 0], [0.5, 2, 2]]\n";

TEST_F(BindScene, BoxFixesTheClosedBoxAndGrabsTheNearestNode) {
  const Problem p = bind_scene(scene(kFixX0, "point = [2.2, 1.9, 2.5]"), cube_);
  ASSERT_EQ(p.constraints.role.size(), 81u);
  for (int n = 0; n < 27; ++n) {
    const bool on_face = p.mesh.nodes(0, n) == 0.0;
    for (int c = 0; c < 3; ++c) {
      const DofRole expected = on_face   ? DofRole::kFixed
                               : n == 26 ? DofRole::kProbe
                                         : DofRole::kFree;
      EXPECT_EQ(role(p, n, c), expected) << "node " << n << " component " << c;
    }
  }
  EXPECT_EQ(p.constraints.probe_nodes, std::vector<int>{26});
  EXPECT_EQ(p.constraints.probe_components, (std::array<bool, 3>{true, true, true}));
  EXPECT_EQ(p.probe_rest, Eigen::Vector3d(2, 2, 2));
  EXPECT_EQ(p.unit, 0.001);
  EXPECT_EQ(p.max_force, 1.5);
  EXPECT_EQ(p.solver.substeps, 7);
  EXPECT_EQ(p.mesh.num_nodes(), 27);
  EXPECT_EQ(p.material.law, Law::kStvk);
  EXPECT_EQ(p.material.mu, 1000.0);
  EXPECT_EQ(p.material.lambda, 4000.0);
  EXPECT_DOUBLE_EQ(p.material.c10, 500.0);
  EXPECT_DOUBLE_EQ(p.material.d1, 2.0 / (4000.0 + 2000.0 / 3.0));
}

TEST_F(BindScene, PlanesWithDefaultAndGivenToleranceAndPartialDofs) {
  const std::string fixed =
      "[[fixed]]\nplane = { point = [0.5, 7, 7], normal = [-2, 0, 0], tolerance = 0.5 }\n"
      "[[fixed]]\nplane = { point = [2, 0, 0], normal = [3, 0, 0] }\ndofs = \"z\"\n";
  const Problem p = bind_scene(scene(fixed, "point = [2, 1, 1]\ndofs = \"y\""), cube_);
  const int grabbed = box_node(2, 1, 1, 3, 3);
  for (int n = 0; n < 27; ++n) {
    const double x = p.mesh.nodes(0, n);
    for (int c = 0; c < 3; ++c) {
      DofRole expected = DofRole::kFree;
      if (x <= 1.0 || (x == 2.0 && c == 2)) expected = DofRole::kFixed;  // |x - 0.5| <= 0.5
      if (n == grabbed && c == 1) expected = DofRole::kProbe;
      EXPECT_EQ(role(p, n, c), expected) << "node " << n << " component " << c;
    }
  }
  EXPECT_EQ(p.constraints.probe_components, (std::array<bool, 3>{false, true, false}));
}

TEST_F(BindScene, GroupSelectorWithMinimalConstraints) {
  // z held on the base, x and y at node 0, y at node 2: exactly the 6 rigid modes removed.
  cube_.groups["base"] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  cube_.groups["side"] = {0, 1};
  const std::string fixed =
      "[[fixed]]\ngroup = \"base\"\ndofs = \"z\"\n"
      "[[fixed]]\nbox = [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]]\ndofs = \"xy\"\n"
      "[[fixed]]\nbox = [[1.5, -0.5, -0.5], [2.5, 0.5, 0.5]]\ndofs = \"y\"\n";
  const Problem p = bind_scene(scene(fixed, "point = [1, 1, 2]"), cube_);
  int fixed_count = 0;
  for (DofRole r : p.constraints.role) fixed_count += r == DofRole::kFixed;
  EXPECT_EQ(fixed_count, 9 + 2 + 1);
  for (int n = 0; n < 9; ++n) EXPECT_EQ(role(p, n, 2), DofRole::kFixed);
  EXPECT_EQ(role(p, 0, 0), DofRole::kFixed);
  EXPECT_EQ(role(p, 0, 1), DofRole::kFixed);
  EXPECT_EQ(role(p, 2, 1), DofRole::kFixed);
  EXPECT_EQ(role(p, 2, 0), DofRole::kFree);
  EXPECT_EQ(role(p, 1, 0), DofRole::kFree);

  EXPECT_EQ(error_of([&] {
              bind_scene(scene("[[fixed]]\ngroup = \"lid\"\n", "point = [1, 1, 2]"), cube_);
            }),
            at(8, "fixed[0]: the mesh has no physical group 'lid' (groups: base, side)"));
}

TEST_F(BindScene, NodeFilesSelectAndReportBadIds) {
  dir_.write("base.txt", "0 1 2  # first row\n3 4 5\n\n6\t7 8\n");
  const Problem p =
      bind_scene(scene("[[fixed]]\nnodes = \"base.txt\"\n", "point = [1, 1, 2]"), cube_);
  for (int n = 0; n < 27; ++n) {
    EXPECT_EQ(role(p, n, 0), n < 9 ? DofRole::kFixed : n == 22 ? DofRole::kProbe : DofRole::kFree);
  }

  const auto bad = dir_.write("bad.txt", "0 1\nfoo 27\n-1 2.5\n");
  EXPECT_EQ(error_of([&] {
              bind_scene(scene("[[fixed]]\nnodes = \"bad.txt\"\n", "point = [1, 1, 2]"), cube_);
            }),
            bad.string() + ":2: 'foo' is not a node id (a 0-based integer)\n" + bad.string() +
                ":2: node id 27 out of range: the mesh has 27 nodes (ids 0..26)\n" + bad.string() +
                ":3: node id -1 out of range: the mesh has 27 nodes (ids 0..26)\n" + bad.string() +
                ":3: '2.5' is not a node id (a 0-based integer)");
}

TEST_F(BindScene, SelectorSelectingNoNodeIsNamed) {
  const std::string fixed = kFixX0 + "[[fixed]]\nbox = [[5, 5, 5], [6, 6, 6.5]]\n" +
                            "[[fixed]]\nplane = { point = [0, 0, 0.5], normal = [0, 0, 1] }\n";
  EXPECT_EQ(error_of([&] { bind_scene(scene(fixed, "point = [2, 2, 2]"), cube_); }),
            at(10, "fixed[1] (box [[5, 5, 5], [6, 6, 6.5]]) selects no node of the mesh") + "\n" +
                at(12,
                   "fixed[2] (plane through [0, 0, 0.5] normal [0, 0, 1]) selects no node of "
                   "the mesh"));
}

TEST_F(BindScene, GrabNearestNodeMayBeInterior) {
  const Problem p = bind_scene(scene(kFixX0, "point = [1.1, 0.9, 1.2]"), cube_);
  EXPECT_EQ(p.constraints.probe_nodes, std::vector<int>{box_node(1, 1, 1, 3, 3)});
  EXPECT_EQ(p.probe_rest, Eigen::Vector3d(1, 1, 1));
}

TEST_F(BindScene, GrabByRadiusTakesSurfaceNodesOnly) {
  const std::string fix_bottom = "[[fixed]]\nbox = [[0, 0, 0], [2, 2, 0.5]]\n";
  const Problem p =
      bind_scene(scene(fix_bottom, "point = [1, 1, 2]\nradius = 1.0\ndofs = \"xy\""), cube_);
  // Within distance 1 of (1, 1, 2): (1,1,2) and its 4 surface neighbours; (1,1,1) is interior.
  const std::vector<int> expected{box_node(1, 0, 2, 3, 3), box_node(0, 1, 2, 3, 3),
                                  box_node(1, 1, 2, 3, 3), box_node(2, 1, 2, 3, 3),
                                  box_node(1, 2, 2, 3, 3)};
  EXPECT_EQ(p.constraints.probe_nodes, expected);
  EXPECT_EQ(role(p, box_node(1, 1, 1, 3, 3), 0), DofRole::kFree);
  EXPECT_TRUE(p.probe_rest.isApprox(Eigen::Vector3d(1, 1, 2)));  // the patch centroid
  EXPECT_EQ(role(p, box_node(2, 1, 2, 3, 3), 0), DofRole::kProbe);
  EXPECT_EQ(role(p, box_node(2, 1, 2, 3, 3), 1), DofRole::kProbe);
  EXPECT_EQ(role(p, box_node(2, 1, 2, 3, 3), 2), DofRole::kFree);
}

TEST_F(BindScene, GrabByRadiusNeedsASurfaceNode) {
  EXPECT_EQ(error_of([&] { bind_scene(scene(kFixX0, "point = [1, 1, 5]\nradius = 0.5"), cube_); }),
            at(10, "probe: no surface node of the mesh within radius 0.5 of [1, 1, 5]"));
}

TEST_F(BindScene, GrabByNodeFile) {
  dir_.write("grab.txt", "26 25 26\n");
  const Problem p = bind_scene(scene(kFixX0, "nodes = \"grab.txt\""), cube_);
  EXPECT_EQ(p.constraints.probe_nodes, (std::vector<int>{25, 26}));
  EXPECT_EQ(p.probe_rest, Eigen::Vector3d(1.5, 2, 2));
}

TEST_F(BindScene, GrabByGroup) {
  Mesh mesh = cube_;
  mesh.groups["tip"] = {25, 26};
  const Problem p = bind_scene(scene(kFixX0, "group = \"tip\""), mesh);
  EXPECT_EQ(p.constraints.probe_nodes, (std::vector<int>{25, 26}));
  EXPECT_EQ(p.probe_rest, Eigen::Vector3d(1.5, 2, 2));
  EXPECT_EQ(error_of([&] { bind_scene(scene(kFixX0, "group = \"nope\""), mesh); }),
            at(10, "probe: the mesh has no physical group 'nope' (groups: tip)"));
}

TEST_F(BindScene, DofBothFixedAndGrabbedIsNamed) {
  dir_.write("grab.txt", "0 26\n");
  EXPECT_EQ(
      error_of([&] {
        bind_scene(
            scene(kFixX0 + "[[fixed]]\ngroup = \"g\"\n", "nodes = \"grab.txt\"\ndofs = \"xz\""),
            [&] {
              Mesh m = cube_;
              m.groups["g"] = {26};
              return m;
            }());
      }),
      at(12, "probe: node 0 component x is both fixed (by fixed[0]) and grabbed by the probe") +
          "\n" +
          at(12,
             "probe: node 0 component z is both fixed (by fixed[0]) and grabbed by the "
             "probe") +
          "\n" +
          at(12,
             "probe: node 26 component x is both fixed (by fixed[1]) and grabbed by the "
             "probe") +
          "\n" +
          at(12,
             "probe: node 26 component z is both fixed (by fixed[1]) and grabbed by the "
             "probe"));
}

TEST_F(BindScene, SingleFixedNodeLeavesRotationAboutTheProbeLine) {
  const std::string fixed = "[[fixed]]\nbox = [[-0.1, -0.1, -0.1], [0.1, 0.1, 0.1]]\n";
  EXPECT_EQ(error_of([&] { bind_scene(scene(fixed, "point = [2, 2, 2]"), cube_); }),
            scene_path().string() +
                ": the constraints leave 1 rigid-body mode(s) free in component 0 of 27 nodes "
                "(e.g. rotation about (0.5774, 0.5774, 0.5774) through (1, 1, 1)); add fixed "
                "nodes");
  // With only z grabbed, rotation about z through node 0 is free too.
  EXPECT_EQ(error_of([&] { bind_scene(scene(fixed, "point = [2, 2, 2]\ndofs = \"z\""), cube_); }),
            scene_path().string() +
                ": the constraints leave 2 rigid-body mode(s) free in component 0 of 27 nodes "
                "(e.g. rotation about z through (0, 0, 1)); add fixed nodes");
}

TEST_F(BindScene, LineOfFixedNodesLeavesRotationAboutTheLine) {
  const Mesh bar = make_box_mesh(4, 3, 3);  // [0, 3] x [0, 2] x [0, 2], centroid (1.5, 1, 1)
  const std::string fixed = "[[fixed]]\nbox = [[-0.1, -0.1, -0.1], [2.1, 0.1, 0.1]]\n";
  EXPECT_EQ(error_of([&] { bind_scene(scene(fixed, "point = [3, 0, 0]"), bar); }),
            scene_path().string() +
                ": the constraints leave 1 rigid-body mode(s) free in component 0 of 36 nodes "
                "(e.g. rotation about x through (1.5, 0, 0)); add fixed nodes");
}

TEST_F(BindScene, GrabbedNodeAloneLeavesThreeRotations) {
  EXPECT_EQ(error_of([&] { bind_scene(scene("", "point = [2, 2, 2]"), cube_); }),
            scene_path().string() +
                ": the constraints leave 3 rigid-body mode(s) free in component 0 of 27 nodes "
                "(e.g. rotation about x through (1, 2, 2)); add fixed nodes");
}

TEST_F(BindScene, GrabbedPatchAloneRemovesAllModes) {
  dir_.write("patch.txt", "0 1 3\n");  // three non-collinear nodes, moving rigidly together
  const Problem p = bind_scene(scene("", "nodes = \"patch.txt\""), cube_);
  EXPECT_EQ(p.constraints.probe_nodes, (std::vector<int>{0, 1, 3}));
}

TEST_F(BindScene, EveryConnectedComponentIsChecked) {
  const Mesh two = merge_meshes(cube_, make_box_mesh(2, 2, 2, 1.0, Eigen::Vector3d(10, 0, 0)));
  EXPECT_EQ(error_of([&] { bind_scene(scene(kFixX0, "point = [2, 2, 2]"), two); }),
            scene_path().string() +
                ": the constraints leave 6 rigid-body mode(s) free in component 1 of 8 nodes "
                "(e.g. translation along x); add fixed nodes");
}

TEST_F(BindScene, ContactProbeCandidatesAreTheSurfaceNodesWithoutFixedComponents) {
  const Problem p =
      bind_scene(scene(kFixX0, "mode = \"contact\"\npoint = [1, 1, 3]\nradius = 0.5"), cube_);
  ASSERT_TRUE(p.contact.has_value());
  EXPECT_EQ(p.contact->radius, 0.5);
  EXPECT_EQ(p.probe_rest, Eigen::Vector3d(1, 1, 3));
  EXPECT_TRUE(p.constraints.probe_nodes.empty());
  // 26 surface nodes (all but the centre (1, 1, 1)), minus the 9 on the fixed face x = 0.
  std::vector<int> expected;
  for (int n = 0; n < 27; ++n)
    if (n != box_node(1, 1, 1, 3, 3) && p.mesh.nodes(0, n) != 0.0) expected.push_back(n);
  EXPECT_EQ(p.contact->candidates, expected);
  for (DofRole r : p.constraints.role) EXPECT_NE(r, DofRole::kProbe);
}

TEST_F(BindScene, ContactSphereOverlappingTheBodyAtRestIsAnError) {
  // Centre 0.4 above the top face: the face point (1, 1, 2) is inside the sphere of radius 0.5.
  EXPECT_EQ(error_of([&] {
              bind_scene(scene(kFixX0, "mode = \"contact\"\npoint = [1, 1, 2.4]\nradius = 0.5"),
                         cube_);
            }),
            at(10,
               "probe: contact: the sphere at rest (centre [1, 1, 2.4], radius 0.5) overlaps "
               "the body: the surface point [1, 1, 2] is at distance 0.4; put probe.point at "
               "least probe.radius away from the body"));
}

TEST_F(BindScene, ContactSphereInsideTheBodyAtRestIsAnError) {
  // Centre (1, 1, 1), 1 from every face of the cube: no surface point within the radius 0.5,
  // but the sphere is inside the body (the winding number of its surface).
  EXPECT_EQ(error_of([&] {
              bind_scene(scene(kFixX0, "mode = \"contact\"\npoint = [1, 1, 1]\nradius = 0.5"),
                         cube_);
            }),
            at(10,
               "probe: contact: the sphere at rest (centre [1, 1, 1], radius 0.5) is inside the "
               "body; put probe.point outside it, at least probe.radius away"));
}

TEST_F(BindScene, ContactProbeNeedsFixedNodesThatHoldTheBody) {
  EXPECT_NE(error_of([&] {
              bind_scene(scene("", "mode = \"contact\"\npoint = [1, 1, 3]\nradius = 0.5"), cube_);
            }).find("rigid-body mode(s) free"),
            std::string::npos);
}

// [loads] and [[support]] (issue 40): gravity lumps the body's weight, a support spreads its
// stiffness over the selected surface, and supports hold the body as fixed nodes do.
TEST_F(BindScene, GravityAndSupportsBecomeBodyLoads) {
  const std::string text =
      kHead + "lambda = 4000\ndensity = 1000\n[loads]\ngravity = [0, 0, -9.81]\n" +
      "[[support]]\nbox = [[-0.1, -0.1, -0.1], [2.1, 2.1, 0.1]]\n" +
      "stiffness = 5e4\ndofs = \"z\"\n[probe]\npoint = [2, 2, 2]\n" + "max_force = 1.5\n" + kTail;
  // Held by the support alone in z: x, y and the rotation about z are free.
  EXPECT_NE(error_of([&] {
              bind_scene(parse_scene(text, scene_path(), {.check_files = false}), cube_);
            }).find("rigid-body mode(s) free"),
            std::string::npos);
  const std::string held = kHead +
                           "lambda = 4000\ndensity = 1000\n[loads]\ngravity = [0, 0, -9.81]\n" +
                           "[[support]]\nbox = [[-0.1, -0.1, -0.1], [2.1, 2.1, 0.1]]\n" +
                           "stiffness = 5e4\n[probe]\npoint = [2, 2, 2]\nmax_force = 1.5\n" + kTail;
  const Problem p = bind_scene(parse_scene(held, scene_path(), {.check_files = false}), cube_);
  // 2 x 2 x 2 mm of density 1000 under g: the weight, lumped to the nodes.
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();
  for (int n = 0; n < 27; ++n) weight += p.loads.force.segment<3>(3 * n);
  EXPECT_NEAR(weight.z(), -1000 * 8e-9 * 9.81, 1e-15);
  // 5e4 N/m^3 over the 4 mm^2 bottom face, in x, y and z.
  EXPECT_NEAR(p.loads.spring.sum(), 3 * 5e4 * 4e-6, 1e-12);
  // The body settled on its support; the grab point followed it.
  ASSERT_EQ(p.rest_m.size(), 81);
  EXPECT_LT(p.probe_sag.z(), 0.0);
  EXPECT_NEAR(p.probe_rest.z(), 2 + p.probe_sag.z(), 1e-15);
  EXPECT_NEAR(p.probe_sag.z() * 1e-3, p.rest_m[3 * 26 + 2], 1e-15);
}

TEST_F(BindScene, LoadsProblemsAreNamed) {
  // A support over the interior line of nodes x = 1, y = 1 touches no surface triangle.
  const std::string line_support =
      kHead + "lambda = 4000\n" + kFixX0 +
      "[[support]]\nbox = [[0.9, 0.9, -0.1], [1.1, 1.1, 2.1]]\n" +
      "stiffness = 1e3\n[probe]\npoint = [2, 2, 2]\nmax_force = 1.5\n" + kTail;
  EXPECT_EQ(error_of([&] {
              bind_scene(parse_scene(line_support, scene_path(), {.check_files = false}), cube_);
            }),
            at(10,
               "support[0] (box [[0.9, 0.9, -0.1], [1.1, 1.1, 2.1]]) selects 3 node(s) but "
               "no surface triangle (one whose three corners are all selected): a support "
               "acts on the surface"));
  // Gravity on a body that only the probe holds: it would fall before the probe takes hold.
  const std::string hanging =
      kHead + "lambda = 4000\ndensity = 1000\n[loads]\n" +
      "gravity = [0, 0, -9.81]\n[probe]\npoint = [1, 1, 2]\nradius = 1.5\n" + "max_force = 1.5\n" +
      kTail;
  // Gravity with a contact probe is refused (its playback takes the rest as the mesh as drawn).
  const std::string contact = kHead + "lambda = 4000\ndensity = 1000\n" + kFixX0 +
                              "[loads]\ngravity = [0, 0, -9.81]\n[probe]\nmode = \"contact\"\n" +
                              "point = [1, 1, 3]\nradius = 0.5\nmax_force = 1.5\n" + kTail;
  EXPECT_NE(error_of([&] {
              bind_scene(parse_scene(contact, scene_path(), {.check_files = false}), cube_);
            }).find("loads.gravity: not supported with a contact probe yet"),
            std::string::npos);
  const std::string fall = error_of(
      [&] { bind_scene(parse_scene(hanging, scene_path(), {.check_files = false}), cube_); });
  EXPECT_NE(fall.find(":9: loads.gravity: the fixed nodes and supports leave 6 rigid-body mode(s)"),
            std::string::npos)
      << fall;
}

// A grab point far from the body is refused with both distances (issue 42); one close by is
// described with its distance.
TEST_F(BindScene, FarGrabPointIsRefusedAndANearOneDescribed) {
  // The cube [0, 2]^3 (diagonal 3.46, edges up to 1.73): 2 units beyond a corner is too far.
  EXPECT_EQ(error_of([&] { bind_scene(scene(kFixX0, "point = [4, 2, 2]"), cube_); }),
            at(10,
               "probe: point [4, 2, 2] is 2 mesh units from the nearest node of the mesh "
               "(node 26 at [2, 2, 2]), more than the 1.73205 allowed (5 % of the mesh's "
               "bounding-box diagonal, or the longest edge at that node if longer): put "
               "probe.point on or near the body's surface"));
  const Scene near = scene(kFixX0, "point = [2.2, 2, 2]");
  EXPECT_EQ(describe_grab(near, bind_scene(near, cube_)),
            "the probe grabs node 26, 0.2 mesh units from probe.point");
}

TEST_F(BindScene, MeshWithoutTets) {
  Mesh empty;
  empty.source = "empty.msh";
  EXPECT_EQ(error_of([&] { bind_scene(scene(kFixX0, "point = [2, 2, 2]"), empty); }),
            scene_path().string() + ": mesh empty.msh has no tetrahedra");
}

TEST(ResolveMaterial, FromYoungPoissonAndFromOwnConstants) {
  SceneMaterial m;
  m.law = Law::kNeoHooke;
  m.young = 5000;
  m.poisson = 0.45;
  const MaterialConstants a = resolve_material(m);
  const double mu = 5000 / 2.9, bulk = 5000 / (3 * 0.1);
  EXPECT_EQ(a.law, Law::kNeoHooke);
  EXPECT_NEAR(a.c10, mu / 2, 1e-9);
  EXPECT_NEAR(a.d1, 2 / bulk, 1e-15);

  SceneMaterial own;
  own.law = Law::kMooney;
  own.c10 = 400;
  own.c01 = 100;
  own.d1 = 1e-3;
  const MaterialConstants b = resolve_material(own);
  EXPECT_EQ(b.law, Law::kMooney);
  EXPECT_EQ(b.c10, 400.0);
  EXPECT_EQ(b.c01, 100.0);
  EXPECT_EQ(b.d1, 1e-3);
  EXPECT_DOUBLE_EQ(b.mu, 1000.0);                     // 2 (c10 + c01)
  EXPECT_DOUBLE_EQ(b.lambda, 2000.0 - 2000.0 / 3.0);  // K - 2 mu / 3, K = 2 / d1
}

}  // namespace
}  // namespace hapstate
