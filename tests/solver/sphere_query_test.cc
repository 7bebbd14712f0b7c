// The grid hash of the contact probe against a plain scan: same points, same order, for radii
// below, at and far above the cell size, and for points spread far apart (hash collisions).
#include "solver/sphere_query.h"

#include <gtest/gtest.h>

#include <random>

namespace hapstate {
namespace {

TEST(SphereQuery, SameAnswerAsAScan) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-5.0, 5.0);
  Eigen::Matrix3Xd points(3, 2000);
  for (int p = 0; p < points.cols(); ++p)
    points.col(p) = Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
  points.col(7) = Eigen::Vector3d(1e6, -1e6, 3e5);  // far away: other cells, same buckets
  SphereQuery index;
  index.build(points, 0.5);
  int nonempty = 0;
  for (double radius : {0.05, 0.5, 1.3, 20.0}) {
    for (int q = 0; q < 200; ++q) {
      const Eigen::Vector3d centre(coord(rng), coord(rng), coord(rng));
      std::vector<int> fast, slow;
      index.inside(centre, radius, &fast);
      points_inside_by_scan(points, centre, radius, &slow);
      ASSERT_EQ(fast, slow) << "radius " << radius << " query " << q;
      nonempty += fast.empty() ? 0 : 1;
    }
  }
  EXPECT_GT(nonempty, 500);
  std::vector<int> far;
  index.inside(Eigen::Vector3d(1e6, -1e6, 3e5), 1e-3, &far);
  EXPECT_EQ(far, std::vector<int>{7});
}

TEST(SphereQuery, EmptySetAndPointsOnTheSphereAreOutside) {
  SphereQuery index;
  std::vector<int> out;
  index.build(Eigen::Matrix3Xd(3, 0), 1.0);
  index.inside(Eigen::Vector3d::Zero(), 1.0, &out);
  EXPECT_TRUE(out.empty());
  Eigen::Matrix3Xd points(3, 2);
  points << 1, 0.5, 0, 0, 0, 0;
  index.build(points, 1.0);
  index.inside(Eigen::Vector3d::Zero(), 1.0, &out);  // strictly inside only
  EXPECT_EQ(out, std::vector<int>{1});
}

}  // namespace
}  // namespace hapstate
