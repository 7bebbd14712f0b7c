// The refine stage's error estimate (statespace/refine_indicator.h) against closed forms.
#include "statespace/refine_indicator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <vector>

namespace hapstate {
namespace {

// A move whose force component r is g[r](s) with derivative dg[r](s).
RecordedMove move_of(const std::function<double(int, double)>& g,
                     const std::function<double(int, double)>& dg) {
  RecordedMove m;
  for (int n = 0; n < 3; ++n)
    for (int r = 0; r < 3; ++r) {
      m.force[n][r] = g(r, 0.5 * n);
      m.slope[n][r] = dg(r, 0.5 * n);
    }
  return m;
}

// The cubic pieces reproduce a cubic force: nothing to refine.
TEST(RefineIndicator, ZeroForACubicForce) {
  const RecordedMove m =
      move_of([](int r, double s) { return (r + 1) * (2.0 - s + 3.0 * s * s - 1.5 * s * s * s); },
              [](int r, double s) { return (r + 1) * (-1.0 + 6.0 * s - 4.5 * s * s); });
  EXPECT_NEAR(half_spacing_error(m), 0.0, 1e-12);
}

// For s^4 the quintic is exact and a cubic Hermite piece of length 1/2 errs by
// (1/2)^4 f'''' / 384 = 1/256 at its middle (s = 1/4 and 3/4): the estimate is the error.
TEST(RefineIndicator, ExactForAQuarticForce) {
  const RecordedMove m = move_of([](int r, double s) { return r == 1 ? 2.0 * s * s * s * s : s; },
                                 [](int r, double s) { return r == 1 ? 8.0 * s * s * s : 1.0; });
  EXPECT_NEAR(half_spacing_error(m), 2.0 / 256.0, 1e-12);
}

// A force that turns within the move (as where a grabbed node's neighbourhood distorts) is
// flagged far above a smooth one of the same size.
TEST(RefineIndicator, LargeWhereTheForceTurns) {
  const RecordedMove smooth =
      move_of([](int, double s) { return std::sin(s); }, [](int, double s) { return std::cos(s); });
  const RecordedMove turning = move_of([](int, double s) { return std::sin(6.0 * s) / 6.0; },
                                       [](int, double s) { return std::cos(6.0 * s); });
  std::printf("[ info ] estimate: sin(s) %.3g, sin(6 s) / 6 %.3g\n", half_spacing_error(smooth),
              half_spacing_error(turning));
  EXPECT_LT(half_spacing_error(smooth), 2e-4);
  EXPECT_GT(half_spacing_error(turning), 30.0 * half_spacing_error(smooth));
}

// An eighth-spacing lattice of a cell of `h` sampling force f and its Jacobian J (p from the cell's
// lowest corner), the samples at the x step `unknown_x` left unknown, with its face neighbours'
// next points (halo_index) when `halo`.
using Vector = std::array<double, 3>;
using Jacobian = std::array<double, 9>;
std::vector<LatticeSample> lattice_of(const Vector& h,
                                      const std::function<Vector(const Vector&)>& f,
                                      const std::function<Jacobian(const Vector&)>& J,
                                      int unknown_x = -2, bool halo = false) {
  std::vector<LatticeSample> out(std::size_t(kHaloSide * kHaloSide * kHaloSide));
  for (int i = -1; i <= 9; ++i)
    for (int j = -1; j <= 9; ++j)
      for (int k = -1; k <= 9; ++k) {
        const int outside = (i < 0 || i > 8) + (j < 0 || j > 8) + (k < 0 || k > 8);
        if (outside > (halo ? 1 : 0)) continue;
        const Vector p = {i * h[0] / 8, j * h[1] / 8, k * h[2] / 8};
        LatticeSample& s = out[halo_index(i, j, k)];
        s.force = f(p), s.stiffness = J(p), s.known = i != unknown_x;
      }
  return out;
}

// Depth 3's choice of eighth cells: none for a cubic force; for a force with a kink across the
// plane x = 2.4 eighth steps exactly the eighth cells on the edges of the runs of three points
// along x that straddle it, (1, 2, 3) and (2, 3, 4): x steps 1 to 3, all across y and z. A run
// with an unknown sample flags nothing.
TEST(RefineIndicator, FlagsTheEighthCellsAroundAKink) {
  const Vector h = {0.4, 0.5, 0.6};
  const auto cubic = lattice_of(
      h,
      [](const Vector& p) {
        return Vector{p[0] * p[1] * p[2], p[1] * p[1] * p[1], 1.0};
      },
      [](const Vector& p) {
        return Jacobian{p[1] * p[2], p[0] * p[2], p[0] * p[1], 0, 3 * p[1] * p[1], 0, 0, 0, 0};
      });
  double largest = -1;
  EXPECT_TRUE(flag_eighth_cells(cubic, h, 1e-12, &largest).empty());
  EXPECT_LT(largest, 1e-12);
  const double x0 = 2.4 * h[0] / 8;
  const auto force = [&](const Vector& p) { return Vector{std::max(0.0, p[0] - x0), 0.0, 0.0}; };
  const auto jacobian = [&](const Vector& p) {
    return Jacobian{p[0] > x0 ? 1.0 : 0.0, 0, 0, 0, 0, 0, 0, 0, 0};
  };
  const std::vector<int> flagged =
      flag_eighth_cells(lattice_of(h, force, jacobian), h, 1e-4, &largest);
  std::printf("[ info ] kink: %zu eighth cells flagged, largest estimate %.3g N\n", flagged.size(),
              largest);
  ASSERT_EQ(flagged.size(), 3u * 64);
  for (const int e : flagged) EXPECT_TRUE(e / 64 >= 1 && e / 64 <= 3) << e;
  // Every run that straddles the kink has a point at x step 2.
  EXPECT_TRUE(flag_eighth_cells(lattice_of(h, force, jacobian, 2), h, 1e-4).empty());
}

// A kink across x = 8.4 eighth steps, just past the cell's upper face, lies in the neighbour's
// first eighth cells: no run inside the cell straddles it, but the run (7, 8, 9) crossing the
// face does, and flags the cell's eighth cells on the edge (7, 8): x step 7, all across y and z.
// So does a kink just before the lower face (x = -0.4 steps) for the edge (0, 1). Without the
// neighbours' points nothing is flagged.
TEST(RefineIndicator, FlagsTheEighthCellsBesideAKinkAcrossAFace) {
  const Vector h = {0.4, 0.5, 0.6};
  for (const double steps : {8.4, -0.4}) {
    const double x0 = steps * h[0] / 8;
    const auto force = [&](const Vector& p) { return Vector{0.0, std::max(0.0, p[0] - x0), 0.0}; };
    const auto jacobian = [&](const Vector& p) {
      return Jacobian{0, 0, 0, p[0] > x0 ? 1.0 : 0.0, 0, 0, 0, 0, 0};
    };
    EXPECT_TRUE(flag_eighth_cells(lattice_of(h, force, jacobian), h, 1e-4).empty()) << steps;
    const std::vector<int> flagged =
        flag_eighth_cells(lattice_of(h, force, jacobian, -2, true), h, 1e-4);
    ASSERT_EQ(flagged.size(), 64u) << steps;
    for (const int e : flagged) EXPECT_EQ(e / 64, steps > 0 ? 7 : 0) << e;
  }
}

// The halo a refined cell's neighbours give it: across each face the neighbour's next point (the
// upper neighbour's step 1 at step 9, the lower one's step 7 at step -1), the cell's own points
// inside, nothing at the halo's edges and corners or where a neighbour is missing; a lattice of
// another size is refused.
TEST(RefineIndicator, LatticeWithHaloTakesTheNeighboursNextPoints) {
  // A lattice whose sample at (i, j, k) carries its steps and `tag` in the force.
  auto tagged = [](double tag) {
    std::vector<LatticeSample> out(729);
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        for (int k = 0; k < 9; ++k) {
          LatticeSample& s = out[std::size_t(81 * i + 9 * j + k)];
          s.force = {tag + i, tag + j, tag + k};
          s.known = true;
        }
    return out;
  };
  const std::vector<LatticeSample> own = tagged(0);
  std::vector<std::vector<LatticeSample>> others;
  for (int n = 0; n < 6; ++n) others.push_back(tagged(100.0 * (n + 1)));
  std::array<const std::vector<LatticeSample>*, 6> neighbour{};
  for (int n = 0; n < 6; ++n) neighbour[std::size_t(n)] = &others[std::size_t(n)];
  const std::vector<LatticeSample> halo = lattice_with_halo(own, neighbour);
  ASSERT_EQ(halo.size(), std::size_t(kHaloSide * kHaloSide * kHaloSide));
  int known = 0;
  for (int i = -1; i <= 9; ++i)
    for (int j = -1; j <= 9; ++j)
      for (int k = -1; k <= 9; ++k) {
        const LatticeSample& s = halo[halo_index(i, j, k)];
        known += s.known;
        const int p[3] = {i, j, k};
        int outside = -1, count = 0;
        for (int a = 0; a < 3; ++a)
          if (p[a] < 0 || p[a] > 8) outside = a, ++count;
        if (count != 1) {
          EXPECT_EQ(s.known, count == 0) << i << " " << j << " " << k;
          if (count == 0)
            EXPECT_EQ(s.force, (std::array<double, 3>{double(i), double(j), double(k)}));
          continue;
        }
        const int side = p[outside] > 8 ? 1 : 0;
        const double tag = 100.0 * (2 * outside + side + 1);
        int q[3] = {i, j, k};
        q[outside] = side ? 1 : 7;
        ASSERT_TRUE(s.known) << i << " " << j << " " << k;
        EXPECT_EQ(s.force, (std::array<double, 3>{tag + q[0], tag + q[1], tag + q[2]}))
            << i << " " << j << " " << k;
      }
  EXPECT_EQ(known, 729 + 6 * 81);
  neighbour[3] = nullptr;  // none across the upper face along y
  const std::vector<LatticeSample> open = lattice_with_halo(own, neighbour);
  for (int i = 0; i < 9; ++i) EXPECT_FALSE(open[halo_index(i, 9, 4)].known);
  EXPECT_TRUE(open[halo_index(4, -1, 4)].known);
  EXPECT_THROW(flag_eighth_cells(own, {0.1, 0.1, 0.1}, 1e-4), std::invalid_argument);
}

}  // namespace
}  // namespace hapstate
