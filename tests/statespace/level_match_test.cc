#include "statespace/level_match.h"

#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include <random>

namespace hapstate {
namespace {

Problem box_problem() {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(4, 1, 1), 8, 2, 2);  // 81 nodes
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    if (p.mesh.nodes(0, n) == 0.0)
      for (int c = 0; c < 3; ++c) p.constraints.role[3 * n + c] = DofRole::kFixed;
  p.constraints.probe_nodes = {80};
  for (int c = 0; c < 3; ++c) p.constraints.role[3 * 80 + c] = DofRole::kProbe;
  return p;
}

TEST(LevelSketch, SixteenNodesNoneFullyFixed) {
  const Problem p = box_problem();
  const LevelSketch sketch(p);
  ASSERT_EQ(sketch.nodes().size(), 16u);
  EXPECT_EQ(sketch.summary_size(), 48);
  for (int n : sketch.nodes()) EXPECT_GT(p.mesh.nodes(0, n), 0.0) << n;
  EXPECT_TRUE(std::is_sorted(sketch.nodes().begin(), sketch.nodes().end()));
  std::vector<double> u(3 * 81);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = static_cast<double>(k);
  const auto s = sketch.summary(u);
  EXPECT_EQ(s[0], 3.0 * sketch.nodes()[0]);
  EXPECT_EQ(s[47], 3.0 * sketch.nodes()[15] + 2);
}

// Contact probe: the touched set is part of the configuration; equal vectors with different
// sets are different levels, equal sets compare as usual.
TEST(LevelDistance, DifferentTouchedSetsAreNeverTheSameLevel) {
  const LevelTolerances tol{0.01, 0.002};
  const ConfigVectors a{std::vector<double>(9, 0.0), {0, 0, 0}, {0.1, 0.2, 0.3}, {2}, {}};
  ConfigVectors b = a;
  EXPECT_EQ(level_distance(a, b, tol), 0.0);
  b.touched = {1};
  EXPECT_TRUE(std::isinf(level_distance(a, b, tol)));
  b.touched.clear();
  EXPECT_TRUE(std::isinf(level_distance(a, b, tol)));
}

TEST(LevelDistance, DefinitionAndBound) {
  const LevelTolerances tol{0.01, 0.002};
  ConfigVectors a{std::vector<double>(9, 0.0), {0, 0, 0}, {0.1, 0.2, 0.3}, {}, {}};
  ConfigVectors b = a;
  EXPECT_EQ(level_distance(a, b, tol), 0.0);
  b.u[4] = 0.005;
  EXPECT_DOUBLE_EQ(level_distance(a, b, tol), 0.5);
  b.h = {0.1, 0.2, 0.3 + 0.004};
  EXPECT_NEAR(level_distance(a, b, tol), 2.0, 1e-12);  // 0.004 N / 0.002 N

  // The bound from summaries and forces never exceeds the distance (random vectors, two probe
  // nodes).
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 0.01);
  for (int trial = 0; trial < 200; ++trial) {
    ConfigVectors x, y;
    for (int k = 0; k < 30; ++k) {
      x.u.push_back(n(rng));
      y.u.push_back(x.u.back() + 0.3 * n(rng));
    }
    for (int k = 0; k < 6; ++k) {
      x.h.push_back(n(rng));
      y.h.push_back(x.h.back() + 0.1 * n(rng));
    }
    auto force = [](const ConfigVectors& v) {
      return std::array<double, 3>{-(v.h[0] + v.h[3]), -(v.h[1] + v.h[4]), -(v.h[2] + v.h[5])};
    };
    const std::vector<double> sx(x.u.begin(), x.u.begin() + 12), sy(y.u.begin(), y.u.begin() + 12);
    const double bound = level_distance_bound(sx, force(x), sy, force(y), tol, 2);
    EXPECT_LE(bound, level_distance(x, y, tol) * (1 + 1e-12)) << trial;
    EXPECT_GT(bound, 0.0);
  }
}

}  // namespace
}  // namespace hapstate
