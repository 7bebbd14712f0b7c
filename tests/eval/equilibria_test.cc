// The two-sided solve's verdict (eval/equilibria.h): its order (a start not reached is never
// taken for an equilibrium that ends), the relative tolerance and the absolute floor. Truth: the
// forces given. The solves themselves are checked on the bunny's sharp vertex, whose two
// branches were measured (tests/python/test_equilibria.py), and at the certificate's worst steps
// (tests/python/test_certificate.py).
#include "eval/equilibria.h"

#include "../common/expect_input_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapstate {
namespace {

Approach converged(double fx, double fz) {
  Approach a;
  a.started = a.converged = true;
  a.force = {fx, 0.0, fz};
  return a;
}

TwoSided sides(const Approach& minus, const Approach& plus) {
  return compare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), minus, plus);
}

TEST(Equilibria, VerdictOrderToleranceAndFloor) {
  const Approach a = converged(0.0, 0.01);
  EXPECT_EQ(judge(sides(a, a)), Equilibria::kOne);
  const TwoSided jump = sides(converged(-2.0e-3, 0.0234), converged(7.33e-3, 0.0222));
  EXPECT_NEAR(jump.difference, std::hypot(9.33e-3, 1.2e-3), 1e-15);
  EXPECT_NEAR(jump.largest, std::max(std::hypot(7.33e-3, 0.0222), std::hypot(2e-3, 0.0234)), 1e-15);
  EXPECT_EQ(judge(jump), Equilibria::kTwo);
  // 2 % of the force apart: two at the default 1 %, one at 5 %.
  EXPECT_EQ(judge(sides(a, converged(2e-4, 0.01))), Equilibria::kTwo);
  EXPECT_EQ(judge(sides(a, converged(2e-4, 0.01)), 0.05), Equilibria::kOne);
  EXPECT_EQ(judge(sides(a, converged(5e-5, 0.01))), Equilibria::kOne);
  // A grazing contact: 5 % of 1 uN is below the absolute floor (1e-7 N).
  EXPECT_EQ(judge(sides(converged(0.0, 1e-6), converged(5e-8, 1e-6))), Equilibria::kOne);
  EXPECT_EQ(judge(sides(converged(0.0, 1e-6), converged(5e-7, 1e-6))), Equilibria::kTwo);

  Approach failed;
  failed.started = true;  // reached its start, then Newton failed
  EXPECT_EQ(judge(sides(failed, a)), Equilibria::kEnds);
  EXPECT_EQ(judge(sides(a, failed)), Equilibria::kEnds);
  EXPECT_TRUE(std::isnan(sides(a, failed).difference));
  EXPECT_EQ(sides(a, failed).largest, 0.01);
  EXPECT_EQ(judge(sides(failed, failed)), Equilibria::kUndecided);
  Approach not_started;  // a start not reached comes first
  EXPECT_EQ(judge(sides(a, not_started)), Equilibria::kUndecided);
  EXPECT_EQ(judge(sides(not_started, failed)), Equilibria::kUndecided);
}

TEST(Equilibria, RefusesABadTolerance) {
  const Approach a = converged(0.0, 0.01);
  for (double bad : {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity()})
    test_util::expect_input_error([&] { judge(sides(a, a), bad); }, {"tolerance"});
}

TEST(Equilibria, NamesAndApproaches) {
  EXPECT_STREQ(equilibria_name(Equilibria::kOne), "one");
  EXPECT_STREQ(equilibria_name(Equilibria::kTwo), "two");
  EXPECT_STREQ(equilibria_name(Equilibria::kEnds), "ends");
  EXPECT_STREQ(equilibria_name(Equilibria::kUndecided), "undecided");
  const auto along = half_spacing_approaches({0.2, 0.4, 0.6});
  EXPECT_EQ(along[0], Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(along[1], Eigen::Vector3d(0, 0.2, 0));
  EXPECT_EQ(along[2], Eigen::Vector3d(0, 0, 0.3));
}

}  // namespace
}  // namespace hapstate
