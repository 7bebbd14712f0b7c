// The bubbles that carry the force between the check-points (playback/cell_bubbles.h): each is
// 1 at its own point and 0 at the points fitted before it, zero with zero slope at the corners,
// zero on every cell face that does not hold its point (so a face's interpolant depends on that
// face's data only), its gradient is the derivative of its weight, and the fit reproduces the
// recorded values at all 19 points.
#include "playback/cell_bubbles.h"
#include "playback/format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hapstate::playback {
namespace {

std::array<double, 3> corner_position(int c) {
  return {double(c >> 2 & 1), double(c >> 1 & 1), double(c & 1)};
}

// Hierarchical: a bubble is 1 at its own point and 0 at the points of the other bubbles of its
// kind and of the kinds fitted before it (an edge's is 1/2 at the centres of its two faces).
TEST(CellBubbles, EachIsOneAtItsPointAndZeroAtTheOthersOfItsKindOrBefore) {
  for (int k = 0; k < kCellBubbles; ++k)
    for (int j = 0; j < kCellBubbles; ++j) {
      if (bubble_spec(j).kind > bubble_spec(k).kind) continue;
      EXPECT_NEAR(bubble_weight(k, bubble_spec(j).point, nullptr), k == j ? 1.0 : 0.0, 1e-15)
          << k << " at " << j;
    }
}

TEST(CellBubbles, TabulatedWeightsAtThePointsAreTheWeights) {
  for (int k = 0; k < kCellBubbles; ++k)
    for (int j = 0; j < kCellBubbles; ++j)
      EXPECT_EQ(bubble_weight_at_point(k, j), bubble_weight(k, bubble_spec(j).point, nullptr))
          << k << " at " << j;
}

TEST(CellBubbles, VanishWithZeroSlopeAtTheCorners) {
  for (int k = 0; k < kCellBubbles; ++k)
    for (int c = 0; c < 8; ++c) {
      std::array<double, 3> g;
      EXPECT_EQ(bubble_weight(k, corner_position(c), &g), 0.0);
      for (double v : g) EXPECT_EQ(v, 0.0) << k << " at corner " << c;
    }
}

// A bubble is non-zero on a cell face only if its point lies on that face (edges of the face,
// the face itself): the interpolants of the two cells sharing a face agree there.
TEST(CellBubbles, ZeroOnTheFacesThatDoNotHoldTheirPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int a = 0; a < 3; ++a)
    for (int o = 0; o < 2; ++o)
      for (int k = 0; k < kCellBubbles; ++k) {
        const bool on_face = bubble_spec(k).point[a] == o;
        for (int n = 0; n < 20; ++n) {
          std::array<double, 3> s{u(rng), u(rng), u(rng)};
          s[a] = o;
          const double w = bubble_weight(k, s, nullptr);
          if (!on_face) {
            EXPECT_EQ(w, 0.0) << k << " on face " << a << "/" << o;
          }
        }
      }
}

TEST(CellBubbles, GradientIsTheDerivativeOfTheWeight) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const double d = 1e-6;
  for (int k = 0; k < kCellBubbles; ++k)
    for (int n = 0; n < 10; ++n) {
      const std::array<double, 3> s{u(rng), u(rng), u(rng)};
      std::array<double, 3> g;
      bubble_weight(k, s, &g);
      for (int a = 0; a < 3; ++a) {
        std::array<double, 3> p = s, m = s;
        p[a] += d;
        m[a] -= d;
        const double fd = (bubble_weight(k, p, nullptr) - bubble_weight(k, m, nullptr)) / (2 * d);
        EXPECT_NEAR(g[a], fd, 1e-8) << k;
      }
    }
}

// The source and target corners of a bubble's move: the move in direction kMidpointOffsets
// [direction] from the source corner ends at the target corner and passes the bubble's point
// half-way.
TEST(CellBubbles, SpecsNameTheMoveThatPassesThePoint) {
  for (int k = 0; k < kCellBubbles; ++k) {
    const BubbleSpec b = bubble_spec(k);
    const auto from = corner_position(b.source_corner), to = corner_position(b.target_corner);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(to[a] - from[a], kMidpointOffsets[b.direction][a]) << k;
      EXPECT_EQ(0.5 * (from[a] + to[a]), b.point[a]) << k;
    }
  }
}

// Whatever the interpolant, the fitted bubbles make it pass through the recorded values at all
// 19 points; a value given for some bubbles only is still reproduced there; the clamp holds.
TEST(CellBubbles, FitReproducesTheRecordedValues) {
  auto interpolant = [](const std::array<double, 3>& s, double* out) {
    for (int r = 0; r < 3; ++r) out[r] = std::sin(1.0 + r + 2 * s[0]) * std::cos(s[1] - s[2] * r);
  };
  auto recorded = [](int k, double* out) {
    for (int r = 0; r < 3; ++r) out[r] = 0.1 * k - 0.3 * r;
    return true;
  };
  const double unlimited[3] = {1e9, 1e9, 1e9};
  std::array<std::array<double, 3>, kCellBubbles> corr;
  fit_bubbles(interpolant, recorded, unlimited, &corr);
  auto with_bubbles = [&](const std::array<double, 3>& s, double* out) {
    interpolant(s, out);
    for (int k = 0; k < kCellBubbles; ++k) {
      const double w = bubble_weight(k, s, nullptr);
      for (int r = 0; r < 3; ++r) out[r] += w * corr[k][r];
    }
  };
  for (int k = 0; k < kCellBubbles; ++k) {
    double got[3], want[3];
    with_bubbles(bubble_spec(k).point, got);
    recorded(k, want);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(got[r], want[r], 1e-13) << k;
  }
  // Only the edges along x and the cell known.
  auto some = [&](int k, double* out) {
    if (!(k < 4 || k == 18)) return false;
    return recorded(k, out);
  };
  fit_bubbles(interpolant, some, unlimited, &corr);
  for (int k = 0; k < kCellBubbles; ++k) {
    double got[3], want[3];
    if (!some(k, want)) {
      for (int r = 0; r < 3; ++r) EXPECT_EQ(corr[k][r], 0.0);
      continue;
    }
    with_bubbles(bubble_spec(k).point, got);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(got[r], want[r], 1e-13) << k;
  }
  const double limit[3] = {0.01, 0.02, 0.03};
  fit_bubbles(interpolant, recorded, limit, &corr);
  for (int k = 0; k < kCellBubbles; ++k)
    for (int r = 0; r < 3; ++r)
      EXPECT_LE(std::abs(corr[k][r]), limit[static_cast<int>(bubble_spec(k).kind)]);
}

}  // namespace
}  // namespace hapstate::playback
