// Refined cells of depth 3 (docs/playback.md, "Refined cells"): the cursor on the synthetic field
// (synthetic.h) with sixteenth-spacing points in some eighth cells of a deep refined cell.
// Exactness at those points, accuracy against depth 2, the depth-2 interpolant unchanged where
// no sixteenth-spacing point was solved, continuity across every face (beside flagged eighth
// cells, unflagged ones, and a deep neighbour without a sixteenth-spacing lattice), the stiffness
// as the force's derivative, and no allocation in the haptic query.
#include "allocation_counter.h"
#include "hapstate/playback.h"
#include "lattice_fixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace hapstate {
namespace {

using test_util::arr;
using test_util::Field;
using test_util::mat;
using test_util::vec;

// The eighth cells (64 i + 8 j + k) of cell (0,0,0) with sixteenth-spacing points: a 2 x 2 x 2
// block in its middle (steps 3-4) and a column along its face x = 0 (steps 0, y 1-2, z 5),
// which borders the deep cell (-1,0,0) without a sixteenth-spacing lattice.
std::vector<int> flagged_eighth_cells() {
  std::vector<int> out;
  for (int i = 3; i <= 4; ++i)
    for (int j = 3; j <= 4; ++j)
      for (int k = 3; k <= 4; ++k) out.push_back(64 * i + 8 * j + k);
  for (int j = 1; j <= 2; ++j) out.push_back(8 * j + 5);
  return out;
}

class SixteenthLattice : public test_util::LatticeFixture {
 protected:
  SixteenthLattice() : LatticeFixture("sixteenth") {}
  // Refined cells (0,0,0), (-1,0,0) and (0,-1,0), the first two at depth 2, and the first with
  // sixteenth-spacing points in flagged_eighth_cells() when `deeper`.
  // With `both`, cell (-1,0,0) has sixteenth-spacing points too, in its eighth cells beside
  // the column (x step 7).
  template <class F>
  playback::Content content(const F& field, bool deeper,
                            const std::vector<std::pair<std::array<int, 3>, int>>& failed = {},
                            bool both = false) {
    playback::Content c = test_util::synthetic_content(field_, h_);
    test_util::add_midpoint_forces(&c, field_, true);
    std::vector<std::pair<std::array<int, 3>, std::vector<int>>> sixteenth;
    if (deeper) sixteenth.push_back({{0, 0, 0}, flagged_eighth_cells()});
    if (both) sixteenth.push_back({{-1, 0, 0}, {64 * 7 + 8 * 1 + 5, 64 * 7 + 8 * 2 + 5}});
    test_util::add_refined_cells(&c, field, {{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}}, failed,
                                 {{0, 0, 0}, {-1, 0, 0}}, sixteenth);
    return c;
  }
};

TEST_F(SixteenthLattice, PassesThroughItsPointsAndChangesNothingElsewhere) {
  playback::Content deeper = content(field_, true);
  ASSERT_EQ(deeper.sixteenth_points.size(), 1u * 12 * playback::kSixteenthPoints);
  // Cell (0,0,0): its face x = 0 borders the deep cell (-1,0,0), which has no sixteenth-spacing
  // lattice: constrained at depth 3, not at depth 2.
  const std::int32_t* r =
      &deeper.refined_cells[playback::kRefinedCellInts * deeper.checkpoints[2 * 62]];
  ASSERT_GE(r[4], 0);
  EXPECT_EQ(r[3] & (1 << playback::refined_face_bit(0, 0)), 0);
  EXPECT_NE(r[5] & (1 << playback::refined_face_bit(0, 0)), 0);
  PlaybackFile with(write(std::move(deeper), "deeper.bin"));
  with.verify();
  PlaybackFile eighth(write(content(field_, false), "eighth.bin"));
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    HapticCursor c(with, scheme), d(eighth, scheme);
    // Exact at the sixteenth-spacing points of the middle block (solved, not constrained).
    double worst = 0, worst_k = 0;
    for (int i = 6; i <= 10; ++i)
      for (int j = 6; j <= 10; ++j)
        for (int k = 6; k <= 10; ++k) {
          const Eigen::Vector3d p = at(i / 16.0, j / 16.0, k / 16.0);
          const Force f = c.force(arr(p));
          worst = std::max(worst, (vec(f.value) - field_.force(p)).norm());
          if (scheme == Scheme::kTrilinear && (i % 2 || j % 2 || k % 2))
            worst_k = std::max(worst_k, (mat(f.stiffness) - field_.jacobian(p)).norm());
        }
    EXPECT_LT(worst, 1e-12);
    EXPECT_LT(worst_k, 1e-12);
    // Where an eighth cell has no sixteenth-spacing point of its own the force is depth 2's, to
    // the last bit: eighth cells far from the flagged ones, and the column on the constrained
    // face x = 0 (its points there keep the eighth cells' interpolant).
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int compared = 0;
    for (int n = 0; n < 300; ++n) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      // The flagged eighth cells and those touching them (sharing their solved points).
      const bool near_block = q.minCoeff() > 0.24 && q.maxCoeff() < 0.76;
      const bool near_column = q[0] < 0.26 && q[1] < 0.51 && q[2] > 0.49 && q[2] < 0.88;
      if (near_block || near_column) continue;
      const Eigen::Vector3d p = at(q[0], q[1], q[2]);
      EXPECT_EQ(vec(c.force(arr(p)).value), vec(d.force(arr(p)).value)) << q.transpose();
      ++compared;
    }
    EXPECT_GT(compared, 100);
  }
  // Inside the middle block: closer to the field than depth 2.
  auto error = [&](const PlaybackFile& file, Scheme scheme) {
    HapticCursor c(file, scheme);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(3.05 / 8, 4.95 / 8);
    double e = 0;
    for (int n = 0; n < 400; ++n) {
      const Eigen::Vector3d p = at(u(rng), u(rng), u(rng));
      e = std::max(e, (vec(c.force(arr(p)).value) - field_.force(p)).norm());
    }
    return e;
  };
  const double deep_h = error(with, Scheme::kHermite), eighth_h = error(eighth, Scheme::kHermite);
  const double deep_t = error(with, Scheme::kTrilinear),
               eighth_t = error(eighth, Scheme::kTrilinear);
  std::printf(
      "[ info ] force error, sixteenth / eighth lattices: Hermite %.3g / %.3g N, trilinear "
      "%.3g / %.3g N\n",
      deep_h, eighth_h, deep_t, eighth_t);
  EXPECT_LT(deep_h, 0.25 * eighth_h);
  EXPECT_LT(deep_t, 0.4 * eighth_t);
}

TEST_F(SixteenthLattice, StaysContinuousAndItsStiffnessIsTheDerivative) {
  // Perturbed points; one sixteenth-spacing point of the middle block failed.
  PlaybackFile file(write(content(test_util::Perturbed<Field>{field_}, true,
                                  {{{0, 0, 0}, kSixteenthFirstPoint + 289 * 7 + 17 * 8 + 9}}),
                          "perturbed.bin"));
  file.verify();
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    HapticCursor c(file, scheme);
    // Random points on faces of sixteenth cells in and around cell (0,0,0).
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::uniform_int_distribution<int> face(-3, 19);
    const double eps = 1e-9;
    double jump = 0;
    for (int n = 0; n < 3000; ++n) {
      const int axis = n % 3;
      Eigen::Vector3d q(u(rng), u(rng), u(rng));
      q[axis] = face(rng) / 16.0;
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = eps;
      const Eigen::Vector3d p = at(q[0], q[1], q[2]);
      jump =
          std::max(jump, (vec(c.force(arr(p + e)).value) - vec(c.force(arr(p - e)).value)).norm());
    }
    std::printf("[ info ] largest jump across a face (%s): %.3g N\n",
                scheme == Scheme::kHermite ? "Hermite" : "trilinear", jump);
    EXPECT_LT(jump, 1e-7);
  }
  HapticCursor cursor(file, Scheme::kHermite);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 20; ++n)
    points.push_back(at(0.36 + 0.013 * n, 0.62 - 0.011 * n, 0.4 + 0.01 * n));
  EXPECT_LT(test_util::stiffness_mismatch(cursor, points), 1e-6);
  // The haptic query allocates nothing, entering sixteenth cells included.
  g_allocations = 0;
  g_counting = true;
  for (int n = 0; n < 200; ++n) cursor.force(arr(at(-0.5 + 0.01 * n, 0.45, 0.5)));
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

// Two neighbouring cells with sixteenth-spacing points on both sides of their shared face: the
// face is not constrained at depth 3, its points hold one value (one of them failed in one
// cell), the force is continuous across the face and exact at the face's solved points.
TEST_F(SixteenthLattice, NeighboursShareTheirFacesPoints) {
  const int failed = kSixteenthFirstPoint + 289 * 16 + 17 * 3 + 11;  // on (-1,0,0)'s face x = 1
  playback::Content c =
      content(test_util::Perturbed<Field>{field_}, true, {{{-1, 0, 0}, failed}}, true);
  const std::int32_t* r = &c.refined_cells[playback::kRefinedCellInts * c.checkpoints[2 * 62]];
  ASSERT_GE(r[4], 0);
  EXPECT_EQ(r[5] & (1 << playback::refined_face_bit(0, 0)), 0);
  PlaybackFile file(write(std::move(c), "both.bin"));
  file.verify();
  const test_util::Perturbed<Field> exact{field_};
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    HapticCursor cursor(file, scheme);
    double jump = 0, worst = 0;
    for (int j = 2; j <= 6; ++j)
      for (int k = 10; k <= 12; ++k) {
        const Eigen::Vector3d p = at(0, j / 16.0, k / 16.0);
        if (j % 2 || k % 2) {
          worst = std::max(worst, (vec(cursor.force(arr(p)).value) - exact.force(p)).norm());
        }
        for (double y : {0.013, 0.029}) {
          const Eigen::Vector3d q = at(0, (j + y) / 16.0, (k + y) / 16.0);
          const Eigen::Vector3d e(1e-9, 0, 0);
          jump = std::max(
              jump,
              (vec(cursor.force(arr(q + e)).value) - vec(cursor.force(arr(q - e)).value)).norm());
        }
      }
    std::printf(
        "[ info ] shared face (%s): largest jump %.3g N, largest error at its points %.3g N\n",
        scheme == Scheme::kHermite ? "Hermite" : "trilinear", jump, worst);
    EXPECT_LT(jump, 1e-7);
    EXPECT_LT(worst, 1e-12);
  }
}

}  // namespace
}  // namespace hapstate
