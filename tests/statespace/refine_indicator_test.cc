// The refine stage's error estimate (statespace/refine_indicator.h) against closed forms.
#include "statespace/refine_indicator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

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

}  // namespace
}  // namespace hapstate
