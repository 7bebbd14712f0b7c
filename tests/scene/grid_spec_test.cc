#include "scene/grid_spec.h"

#include "util/error.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

SceneGrid spacing_grid(double h, std::optional<Box> box = std::nullopt) {
  SceneGrid g;
  g.spacing = Eigen::Vector3d::Constant(h);
  g.box = box;
  return g;
}

// grid.dims = [3, 3, 3] over the unit box: spacing 0.5.
SceneGrid unit_box_dims3() {
  SceneGrid g;
  g.dims = std::array<int, 3>{3, 3, 3};
  g.box = Box{{0, 0, 0}, {1, 1, 1}};
  return g;
}

TEST(GridSpec, RestPositionIsCheckpointZero) {
  const Eigen::Vector3d rest(4.0, 0.5, 1.0);
  const GridSpec g =
      resolve_grid(spacing_grid(0.1, Box{{3.8, 0.4, 0.9}, {4.2, 0.6, 1.1}}), rest, "s");
  EXPECT_EQ(g.position({0, 0, 0}), rest);
  EXPECT_EQ(g.lo, (GridIndex{-2, -1, -1}));
  EXPECT_EQ(g.hi, (GridIndex{2, 1, 1}));
  EXPECT_EQ(g.num_checkpoints(), 45);
  EXPECT_NEAR(g.position({2, -1, 1}).x(), 4.2, 1e-15);
  EXPECT_NEAR(g.position({2, -1, 1}).y(), 0.4, 1e-15);
  EXPECT_TRUE(g.in_workspace(g.position({2, 1, 1})));
  EXPECT_FALSE(g.in_workspace(g.position({3, 1, 1})));
}

TEST(GridSpec, UnalignedBoxKeepsTheCheckpointsInside) {
  // The box edges are not on the grid through the rest position: check-points stay inside.
  const GridSpec g = resolve_grid(spacing_grid(0.25, Box{{-1.1, -0.3, -0.6}, {0.9, 0.3, 0.6}}),
                                  Eigen::Vector3d::Zero(), "s");
  EXPECT_EQ(g.lo, (GridIndex{-4, -1, -2}));
  EXPECT_EQ(g.hi, (GridIndex{3, 1, 2}));
}

TEST(GridSpec, DefaultWorkspaceIsFourSpacingsEachWay) {
  const GridSpec g = resolve_grid(spacing_grid(0.25), Eigen::Vector3d(1, 2, 3), "s");
  EXPECT_EQ(g.lo, (GridIndex{-4, -4, -4}));
  EXPECT_EQ(g.hi, (GridIndex{4, 4, 4}));
  EXPECT_EQ(g.num_checkpoints(), 729);
  EXPECT_EQ(g.workspace.min, Eigen::Vector3d(0, 1, 2));
}

TEST(GridSpec, DimsGiveTheSpacing) {
  SceneGrid s;
  s.dims = std::array<int, 3>{5, 3, 2};
  s.box = Box{{0, 0, 0}, {2, 1, 1}};
  const GridSpec g = resolve_grid(s, Eigen::Vector3d(1.0, 0.5, 0.0), "s");
  EXPECT_EQ(g.spacing, Eigen::Vector3d(0.5, 0.5, 1.0));
  EXPECT_EQ(g.num_checkpoints(), 5 * 3 * 2);
}

// A box written with rounded numbers: its edges miss the lattice through the rest position by
// 1e-4 of a spacing. dims are kept (snapped within 1e-3 spacings) and the workspace grows to
// the snapped check-points; nothing is reported.
TEST(GridSpec, RoundedBoxEdgesSnapToTheLattice) {
  const SceneGrid s = unit_box_dims3();
  const GridSpec g = resolve_grid(s, Eigen::Vector3d(0.50005, 0.49995, 0.5), "s");
  EXPECT_EQ(g.num_checkpoints(), 27);
  EXPECT_TRUE(g.in_workspace(g.position(g.lo)));
  EXPECT_TRUE(g.in_workspace(g.position(g.hi)));
  EXPECT_NEAR(g.workspace.max.x(), 1.00005, 1e-12);
  EXPECT_NEAR(g.workspace.min.y(), -0.00005, 1e-12);
  EXPECT_TRUE(grid_short_axes(s, g, "s").empty());
}

// A box edge on the lattice up to rounding keeps the workspace as written (so the grid's hash
// of an unchanged scene does not change): 0 + (-3) * 0.1 is -0.30000000000000004.
TEST(GridSpec, EdgesOnTheLatticeKeepTheWorkspace) {
  const Box box{{-0.3, -0.3, -0.3}, {0.3, 0.3, 0.3}};
  const GridSpec g = resolve_grid(spacing_grid(0.1, box), Eigen::Vector3d::Zero(), "s");
  EXPECT_EQ(g.workspace.min, box.min);
  EXPECT_EQ(g.workspace.max, box.max);
  EXPECT_EQ(g.num_checkpoints(), 7 * 7 * 7);
}

// Beyond the snapping tolerance the axis loses check-points, and the message says which axis,
// how many, and by how much to shift the box.
TEST(GridSpec, ShortAxisIsReported) {
  const SceneGrid s = unit_box_dims3();
  const GridSpec g = resolve_grid(s, Eigen::Vector3d(0.5, 0.3, 0.5), "scene.toml");
  EXPECT_EQ(g.num_checkpoints(), 3 * 2 * 3);
  const std::vector<std::string> notes = grid_short_axes(s, g, "scene.toml");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("scene.toml: [grid] dims asks for 3 check-points along y but box holds "
                          "2"),
            std::string::npos)
      << notes[0];
  EXPECT_NE(notes[0].find("rest position y = 0.3"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("0.4 spacings off"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("shift grid.box by -0.2 along y"), std::string::npos) << notes[0];
}

TEST(GridSpec, EnlargingTheWorkspaceKeepsPositionsAndHash) {
  const Eigen::Vector3d rest(0.3, 0.1, 0.2);
  const GridSpec small =
      resolve_grid(spacing_grid(0.1, Box{{0.1, 0.0, 0.0}, {0.5, 0.2, 0.4}}), rest, "s");
  const GridSpec large =
      resolve_grid(spacing_grid(0.1, Box{{0.0, -0.1, 0.0}, {0.6, 0.3, 0.4}}), rest, "s");
  for (int i = small.lo[0]; i <= small.hi[0]; ++i)
    EXPECT_EQ(small.position({i, 1, 0}), large.position({i, 1, 0}));
  EXPECT_LT(large.lo[0], small.lo[0]);
  EXPECT_NE(small.hash(), large.hash());
  EXPECT_EQ(small.hash(), resolve_grid(spacing_grid(0.1, small.workspace), rest, "s").hash());
}

TEST(GridSpec, AbsurdlyManyCheckpointsIsAnError) {
  try {
    resolve_grid(spacing_grid(1e-4, Box{{0, 0, 0}, {1, 1, 1}}), Eigen::Vector3d(0.5, 0.5, 0.5),
                 "scene.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.toml: [grid] spacing (0.0001, 0.0001, 0.0001) over "
                                         "the box gives 1e+12 check-points"),
              std::string::npos)
        << e.what();
  }
}

TEST(GridSpec, RestOutsideTheBoxIsAnError) {
  try {
    resolve_grid(spacing_grid(0.1, Box{{0, 0, 0}, {1, 1, 1}}), Eigen::Vector3d(2, 0.5, 0.5),
                 "scene.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.toml: [grid] box"), std::string::npos) << e.what();
    EXPECT_NE(
        std::string(e.what()).find("does not contain the probe's rest position (2, 0.5, 0.5)"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hapstate
