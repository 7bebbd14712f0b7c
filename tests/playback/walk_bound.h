// Drives a cursor along a seeded random walk of 1 ms steps (1 % fast moves of about a grid
// spacing, excursions up to one spacing outside the grid) and checks finiteness and the
// documented bound |Δf| <= force_change_bound() |Δp| between consecutive steps.
#pragma once

#include "hapstate/playback.h"

#include <gtest/gtest.h>
#include <Eigen/Core>

#include <random>

namespace hapstate::test_util {

// Returns the worst |Δf| / |Δp| divided by the bound (<= 1 when the bound holds).
inline double check_bound_along_random_walk(const PlaybackFile& file, Scheme scheme, int steps,
                                            double slow_step_spacings = 0.03) {
  HapticCursor cursor(file, scheme);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const auto o = file.grid_origin(), h = file.grid_spacing();
  const auto lo = file.grid_lo(), dims = file.grid_dims();
  const auto rest = file.rest_position();
  Eigen::Vector3d p(rest[0], rest[1], rest[2]);
  const auto f0 = cursor.force(rest).value;
  Eigen::Vector3d f_prev(f0[0], f0[1], f0[2]);
  const double bound = file.force_change_bound();
  double worst = 0;
  for (int s = 0; s < steps; ++s) {
    Eigen::Vector3d step(n(rng) * h[0], n(rng) * h[1], n(rng) * h[2]);
    step *= uni(rng) < 0.01 ? 1.0 : slow_step_spacings;
    Eigen::Vector3d next = p + step;
    for (int a = 0; a < 3; ++a) {
      const double lo_p = o[a] + (lo[a] - 1.0) * h[a], hi_p = o[a] + (lo[a] + dims[a]) * h[a];
      if (next[a] < lo_p || next[a] > hi_p) next[a] = p[a] - step[a];
    }
    const auto fv = cursor.force({next[0], next[1], next[2]}).value;
    const Eigen::Vector3d f(fv[0], fv[1], fv[2]);
    EXPECT_TRUE(f.allFinite()) << "step " << s;
    if (!f.allFinite()) return INFINITY;
    const double change = (f - f_prev).norm(), move = (next - p).norm();
    EXPECT_LE(change, bound * move + 1e-12) << "step " << s;
    if (move > 0) worst = std::max(worst, change / move / bound);
    p = next;
    f_prev = f;
  }
  return worst;
}

}  // namespace hapstate::test_util
