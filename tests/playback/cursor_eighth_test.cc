// Refined cells of depth 2 (docs/playback.md, "Refined cells"): the cursor on the synthetic field
// (synthetic.h) with eighth-spacing lattices in some refined cells. Exactness at their points,
// accuracy against quarter-spacing refinement alone, continuity across every face (eighth cells
// beside eighth cells, beside quarter cells, beside cells that are not refined), the stiffness as
// the force's derivative, and no allocation in the haptic query.
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

class EighthLattice : public test_util::LatticeFixture {
 protected:
  EighthLattice() : LatticeFixture("eighth") {}
  // Refined cells (0,0,0), (-1,0,0) and (0,-1,0); the first two also at depth 2 when `deep`.
  template <class F>
  playback::Content content(const F& field, bool deep,
                            const std::vector<std::pair<std::array<int, 3>, int>>& failed = {}) {
    playback::Content c = test_util::synthetic_content(field_, h_);
    test_util::add_midpoint_forces(&c, field_, true);
    test_util::add_refined_cells(&c, field, {{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}}, failed,
                                 deep ? std::vector<std::array<int, 3>>{{0, 0, 0}, {-1, 0, 0}}
                                      : std::vector<std::array<int, 3>>{});
    return c;
  }
  // The largest jump of the force across 1 500 random points on faces of eighth cells.
  double max_jump(HapticCursor& c) const {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-1.999, 1.999);
    std::uniform_int_distribution<int> face(-16, 16);
    const double eps = 1e-9;
    double jump = 0;
    for (int n = 0; n < 1500; ++n) {
      const int axis = n % 3;
      Eigen::Vector3d q(u(rng), u(rng), u(rng));
      q[axis] = 0.125 * face(rng);
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = eps;
      const Eigen::Vector3d p = at(q[0], q[1], q[2]);
      jump =
          std::max(jump, (vec(c.force(arr(p + e)).value) - vec(c.force(arr(p - e)).value)).norm());
    }
    return jump;
  }
};

TEST_F(EighthLattice, PassesThroughItsPointsAndIsMoreAccurate) {
  playback::Content deep = content(field_, true);
  ASSERT_EQ(deep.eighth_points.size(), 2u * 12 * playback::kEighthPoints);
  // Cell (0,0,0): its face x = 0 borders the deep cell (-1,0,0), its face y = 0 the refined cell
  // (0,-1,0), which has no eighth-spacing lattice: constrained at depth 2 only.
  const std::int32_t* r =
      &deep.refined_cells[playback::kRefinedCellInts * deep.checkpoints[2 * 62]];
  EXPECT_GE(r[2], 0);
  EXPECT_EQ(r[1] & (1 << playback::refined_face_bit(1, 0)), 0);
  EXPECT_NE(r[3] & (1 << playback::refined_face_bit(1, 0)), 0);
  EXPECT_EQ(r[3] & (1 << playback::refined_face_bit(0, 0)), 0);
  PlaybackFile with(write(std::move(deep), "deep.bin"));
  with.verify();
  PlaybackFile quarter(write(content(field_, false), "quarter.bin"));
  HapticCursor hermite(with, Scheme::kHermite), trilinear(with, Scheme::kTrilinear);
  // Exact at the eighth-spacing points inside the deep pair (off its outer faces).
  double worst = 0, worst_trilinear = 0, worst_k = 0;
  for (int i = 1; i < 16; ++i)
    for (int j = 1; j < 8; ++j)
      for (int k = 1; k < 8; ++k) {
        const Eigen::Vector3d p = at(-1.0 + 0.125 * i, 0.125 * j, 0.125 * k);
        worst = std::max(worst, (vec(hermite.force(arr(p)).value) - field_.force(p)).norm());
        const Force t = trilinear.force(arr(p));
        worst_trilinear = std::max(worst_trilinear, (vec(t.value) - field_.force(p)).norm());
        if (i % 2 || j % 2 || k % 2)
          worst_k = std::max(worst_k, (mat(t.stiffness) - field_.jacobian(p)).norm());
      }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_trilinear, 1e-12);
  EXPECT_LT(worst_k, 1e-12);
  // Inside the pair, away from its outer faces (constrained: within a quarter spacing of them the
  // coarser interpolant's error reaches in): closer to the field than the quarter cells.
  auto error = [&](const PlaybackFile& file, Scheme scheme) {
    HapticCursor c(file, scheme);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.3, 0.7);
    double e = 0;
    for (int n = 0; n < 400; ++n) {
      const Eigen::Vector3d p = at(3.5 * u(rng) - 1.75, u(rng), u(rng));
      e = std::max(e, (vec(c.force(arr(p)).value) - field_.force(p)).norm());
    }
    return e;
  };
  const double deep_h = error(with, Scheme::kHermite), quarter_h = error(quarter, Scheme::kHermite);
  const double deep_t = error(with, Scheme::kTrilinear),
               quarter_t = error(quarter, Scheme::kTrilinear);
  std::printf(
      "[ info ] force error, eighth / quarter lattices: Hermite %.3g / %.3g N, trilinear "
      "%.3g / %.3g N\n",
      deep_h, quarter_h, deep_t, quarter_t);
  EXPECT_LT(deep_h, 0.25 * quarter_h);
  EXPECT_LT(deep_t, 0.4 * quarter_t);
}

TEST_F(EighthLattice, StaysContinuousAndItsStiffnessIsTheDerivative) {
  // Perturbed points; two points of the deep pair's shared face failed in one of the two cells.
  PlaybackFile file(write(
      content(test_util::Perturbed<Field>{field_}, true,
              {{{0, 0, 0}, 125 + 0 * 81 + 9 * 3 + 5}, {{-1, 0, 0}, 125 + 8 * 81 + 9 * 1 + 2}}),
      "perturbed.bin"));
  file.verify();
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    HapticCursor c(file, scheme);
    const double jump = max_jump(c);
    std::printf("[ info ] largest jump across a face (%s): %.3g N\n",
                scheme == Scheme::kHermite ? "Hermite" : "trilinear", jump);
    EXPECT_LT(jump, 1e-7);
  }
  HapticCursor cursor(file, Scheme::kHermite);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 20; ++n)
    points.push_back(at(-0.95 + 0.09 * n, 0.3 + 0.02 * n, 0.9 - 0.04 * n));
  EXPECT_LT(test_util::stiffness_mismatch(cursor, points), 1e-6);
  // The haptic query allocates nothing, entering deep cells included.
  g_allocations = 0;
  g_counting = true;
  for (int n = 0; n < 200; ++n) cursor.force(arr(at(-1.0 + 0.01 * n, 0.5, 0.5)));
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

}  // namespace
}  // namespace hapstate
