// Point-to-triangle distance and its derivatives against independent truths: the closest point
// against a dense brute-force search over the triangle, the gradient and Hessian against central
// differences of the distance, in every region (face, three edges, three corners); the
// segment-to-triangle distance against sampling the segment.
#include "solver/triangle_distance.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace hapstate {
namespace {

double brute_force_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& q) {
  double best = 1e300;
  const int n = 400;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Eigen::Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
      best = std::min(best, (q - p).norm());
    }
  return best;
}

double distance_of(const Vec12d& y) {
  return closest_point(y.segment<3>(0), y.segment<3>(3), y.segment<3>(6), y.segment<3>(9)).distance;
}

struct Case {
  Eigen::Vector3d a, b, c, q;
};

// A triangle and points in each of its seven regions, off the plane.
std::vector<Case> cases() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  const Eigen::Vector3d a(0.1, -0.2, 0.05), b(1.3, 0.1, -0.1), c(0.4, 1.1, 0.2);
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d centroid = (a + b + c) / 3;
  std::vector<Eigen::Vector3d> in_plane = {
      centroid,                                // face
      a + (a - centroid) * 0.8,                // corner a
      b + (b - centroid) * 0.8,                // corner b
      c + (c - centroid) * 0.8,                // corner c
      (a + b) / 2 + ((a + b) / 2 - centroid),  // edge ab
      (b + c) / 2 + ((b + c) / 2 - centroid),  // edge bc
      (c + a) / 2 + ((c + a) / 2 - centroid),  // edge ca
  };
  std::vector<Case> out;
  for (const Eigen::Vector3d& p : in_plane)
    for (double h : {0.3, -0.7}) {
      const Eigen::Vector3d j(jitter(rng), jitter(rng), jitter(rng));
      out.push_back({a, b, c, p + h * n + j});
    }
  return out;
}

TEST(TriangleDistance, ClosestPointMatchesBruteForceInEveryRegion) {
  for (const Case& k : cases()) {
    const TrianglePoint tp = closest_point(k.a, k.b, k.c, k.q);
    EXPECT_NEAR(tp.weights.sum(), 1.0, 1e-14);
    EXPECT_GE(tp.weights.minCoeff(), 0.0);
    EXPECT_NEAR(
        (tp.closest - (tp.weights[0] * k.a + tp.weights[1] * k.b + tp.weights[2] * k.c)).norm(), 0,
        1e-14);
    // The brute force's grid of 1/400 of the edges bounds its own error by ~2e-3.
    const double brute = brute_force_distance(k.a, k.b, k.c, k.q);
    EXPECT_LE(tp.distance, brute + 1e-12);
    EXPECT_GE(tp.distance, brute - 5e-3);
  }
}

TEST(TriangleDistance, DerivativesMatchCentralDifferencesInEveryRegion) {
  int regions[4] = {0, 0, 0, 0};  // by number of corners with non-zero weight
  for (const Case& k : cases()) {
    Vec12d y;
    y << k.a, k.b, k.c, k.q;
    const TrianglePoint tp = closest_point(k.a, k.b, k.c, k.q);
    int corners = 0;
    for (int i = 0; i < 3; ++i) corners += tp.weights[i] > 0 ? 1 : 0;
    ++regions[corners];
    Vec12d g;
    Mat12d h;
    distance_derivatives(k.a, k.b, k.c, k.q, tp, &g, &h);
    ASSERT_GT(g.norm(), 0.5);  // |dd/dq| = 1
    const double eps = 1e-5;
    for (int i = 0; i < 12; ++i) {
      Vec12d yp = y, ym = y;
      yp[i] += eps;
      ym[i] -= eps;
      EXPECT_NEAR(g[i], (distance_of(yp) - distance_of(ym)) / (2 * eps), 1e-8) << "gradient " << i;
      Vec12d gp, gm;
      Mat12d unused;
      distance_derivatives(
          yp.segment<3>(0), yp.segment<3>(3), yp.segment<3>(6), yp.segment<3>(9),
          closest_point(yp.segment<3>(0), yp.segment<3>(3), yp.segment<3>(6), yp.segment<3>(9)),
          &gp, &unused);
      distance_derivatives(
          ym.segment<3>(0), ym.segment<3>(3), ym.segment<3>(6), ym.segment<3>(9),
          closest_point(ym.segment<3>(0), ym.segment<3>(3), ym.segment<3>(6), ym.segment<3>(9)),
          &gm, &unused);
      const Vec12d column = (gp - gm) / (2 * eps);
      EXPECT_LE((h.col(i) - column).norm(), 1e-6 * std::max(1.0, h.norm()))
          << "Hessian column " << i;
    }
    EXPECT_LE((h - h.transpose()).norm(), 1e-12 * h.norm());
    EXPECT_GT(h.norm(), 0.1);  // not trivially zero
  }
  EXPECT_EQ(regions[1], 6);  // corners
  EXPECT_EQ(regions[2], 6);  // edges
  EXPECT_EQ(regions[3], 2);  // face
}

TEST(TriangleDistance, SegmentDistanceMatchesSampling) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  int crossings = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng));
    const double d = segment_triangle_distance(p0, p1, a, b, c);
    double sampled = 1e300;
    for (int s = 0; s <= 2000; ++s)
      sampled = std::min(sampled, closest_point(a, b, c, p0 + (p1 - p0) * (s / 2000.0)).distance);
    crossings += d == 0.0 ? 1 : 0;
    EXPECT_LE(d, sampled + 1e-12) << trial;
    EXPECT_GE(d, sampled - 2e-3 * (p1 - p0).norm()) << trial;
  }
  EXPECT_GT(crossings, 5);
}

}  // namespace
}  // namespace hapstate
