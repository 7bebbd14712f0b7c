#include "playback/onset_model.h"

#include "util/grid_direction.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace hapstate::playback {

std::vector<OnsetCorner> onset_corners(const Content& c) {
  const std::size_t n = c.config_checkpoint.size();
  std::vector<OnsetCorner> out(n, OnsetCorner{});
  const double* h = c.meta.spacing;
  const double shallow = 1e-3 * std::min({h[0], h[1], h[2]});
  auto gap = [&](std::size_t config) {
    return &c.clearance[4 * static_cast<std::size_t>(c.config_checkpoint[config])];
  };
  auto deep = [&](std::size_t k) { return c.config_zero[k] != 1 && -gap(k)[0] >= shallow; };
  for (std::size_t k = 0; k < n; ++k) {
    OnsetCorner& o = out[k];
    o.source = -1;
    o.depth_source = -1;
    if (!deep(k)) continue;
    const double* g = gap(k);
    const double d = -g[0];
    const double* f = &c.force[3 * k];
    // The force along the depth: f' = K d p / d d, with d p / d d = -grad g / |grad g|^2.
    const double* K = &c.stiffness[9 * k];
    const double gg = g[1] * g[1] + g[2] * g[2] + g[3] * g[3];
    double fd[3] = {0, 0, 0};
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) fd[r] -= K[3 * r + a] * g[1 + a] / gg;
    const double ff = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
    // f(x) = (f / d) x (1 + beta (x / d - 1)), with f'(d) along f matching: beta = 0 for a force
    // proportional to the depth, 1/2 for Hertz's d^1.5; limited to [-1/2, 1].
    double beta =
        ff > 0.0 && gg > 0.0 ? d * (f[0] * fd[0] + f[1] * fd[1] + f[2] * fd[2]) / ff - 1.0 : 0.0;
    beta = std::isfinite(beta) ? std::clamp(beta, -0.5, 1.0) : 0.0;
    for (int r = 0; r < 3; ++r) {
      o.per_depth[r] = f[r] / d * (1.0 - beta);
      o.per_depth_squared[r] = f[r] / d * beta / d;
    }
    o.depth_source = static_cast<std::int32_t>(k);
    o.displacement_per_depth = 1.0 / d;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double* gk = gap(k);
    const bool free = c.config_zero[k] == 1 && gk[0] >= 0.0;
    const bool at_onset = c.config_zero[k] != 1 && gk[0] < 0.0 && -gk[0] < shallow;
    if (!free && !at_onset) continue;
    OnsetCorner& o = out[k];
    o.depth_source = static_cast<std::int32_t>(k);  // q = 0, no displacements if no neighbour
    int used = 0;
    // Directions by grid distance (taxicab 1: straight, 2: face diagonal, 3: body diagonal),
    // numbered as in util/grid_direction.h; the nearest distance with a neighbour is used.
    for (int dist = 1; dist <= 3 && used == 0; ++dist)
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk) {
            if (std::abs(di) + std::abs(dj) + std::abs(dk) != dist) continue;
            const int d = grid::direction_index(di, dj, dk);
            const std::int32_t t =
                c.transitions[grid::kDirections * k + static_cast<std::size_t>(d)];
            if (t < 0 || static_cast<std::size_t>(t) >= n || !deep(static_cast<std::size_t>(t)))
              continue;
            const OnsetCorner& ot = out[static_cast<std::size_t>(t)];
            const double dt = -gap(static_cast<std::size_t>(t))[0];
            double qt[3];  // the secant f_t / d_t
            for (int r = 0; r < 3; ++r) {
              o.per_depth[r] += ot.per_depth[r];
              o.per_depth_squared[r] += ot.per_depth_squared[r];
              qt[r] = ot.per_depth[r] + ot.per_depth_squared[r] * dt;
            }
            if (used++ == 0) {
              o.depth_source = t;
              o.displacement_per_depth = ot.displacement_per_depth;
            }
            if (!free) continue;
            // The secant model: f_t / d_t x d_k = q_t d_k (d_k = -g_k <= 0 here).
            for (int r = 0; r < 3; ++r) {
              o.force[r] -= qt[r] * gk[0];
              for (int a = 0; a < 3; ++a) o.stiffness[3 * r + a] -= qt[r] * gk[1 + a];
            }
            if (o.source < 0) {
              o.source = t;
              for (int s = 0; s < 4; ++s) o.secant[s] = -gk[s] / dt;
            }
          }
    const double mean = 1.0 / std::max(used, 1);
    for (double& v : o.force) v *= mean;
    for (double& v : o.stiffness) v *= mean;
    for (double& v : o.per_depth) v *= mean;
    for (double& v : o.per_depth_squared) v *= mean;
  }
  return out;
}

}  // namespace hapstate::playback
