// The depth model of one touching state (docs/playback.md, "Contact onset"): the force at depth x
// into the rest body, m(x) = x (a + b x), through the state's force f at its depth d with the
// slope its stiffness K has along the depth. One definition for hapstate-index (a configuration's
// model, section 15) and the cursor (a refined point's, in a refined cell near the onset).
// Allocation-free.
#pragma once

#include <algorithm>
#include <cmath>

namespace hapstate::playback {

// A state touching by less than this (10^-3 of the smallest spacing) has no depth model of its
// own: f / d would be a ratio of rounding errors.
inline double shallow_depth(const double* spacing) {
  return 1e-3 * std::min({spacing[0], spacing[1], spacing[2]});
}

// `gap` is the clearance at the state's position and its gradient (4 values, the depth d = -gap[0]
// > 0), `band` the blending band's width (onset_band); writes a (per_depth) and b
// (per_depth_squared), 3 values each.
inline void depth_model(const double* f, const double* K, const double* gap, double band,
                        double* per_depth, double* per_depth_squared) {
  const double d = -gap[0];
  // The force along the depth: f' = K d p / d d, with d p / d d = -grad g / |grad g|^2.
  const double gg = gap[1] * gap[1] + gap[2] * gap[2] + gap[3] * gap[3];
  double fd[3] = {0, 0, 0};
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) fd[r] -= K[3 * r + a] * gap[1 + a] / gg;
  const double ff = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
  // f(x) = (f / d) x (1 + beta (x / d - 1)), with f'(d) along f matching: beta = 0 for a force
  // proportional to the depth, 1/2 for Hertz's d^1.5. Limited to [-1/2, 1] (a stiffness
  // one-sided at a kink can be several times its neighbours'), and so that over the band, where
  // the cursor uses the model, its slope stays >= 0 (beta >= -d / (2 band - d)) and its
  // quadratic term no larger than its linear one (beta <= d / (d + band)): the model of a
  // state shallower than the band is extrapolated, and its curvature, b = beta f / d^2, would
  // grow as 1 / d.
  double beta =
      ff > 0.0 && gg > 0.0 ? d * (f[0] * fd[0] + f[1] * fd[1] + f[2] * fd[2]) / ff - 1.0 : 0.0;
  const double lowest = 2.0 * band > d ? std::max(-0.5, -d / (2.0 * band - d)) : -0.5;
  beta = std::isfinite(beta) ? std::clamp(beta, lowest, std::min(1.0, d / (d + band))) : 0.0;
  for (int r = 0; r < 3; ++r) {
    per_depth[r] = f[r] / d * (1.0 - beta);
    per_depth_squared[r] = f[r] / d * beta / d;
  }
}

}  // namespace hapstate::playback
