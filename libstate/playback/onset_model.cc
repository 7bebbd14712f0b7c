#include "playback/onset_model.h"

#include "util/grid_direction.h"

#include <algorithm>
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
    const double d = -gap(k)[0];
    for (int r = 0; r < 3; ++r) o.per_depth[r] = c.force[3 * k + r] / d;
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
            for (int r = 0; r < 3; ++r) o.per_depth[r] += ot.per_depth[r];
            if (used++ == 0) {
              o.depth_source = t;
              o.displacement_per_depth = ot.displacement_per_depth;
            }
            if (!free) continue;
            // The secant model: f_t / d_t x d_k = q_t d_k (d_k = -g_k <= 0 here).
            for (int r = 0; r < 3; ++r) {
              o.force[r] -= ot.per_depth[r] * gk[0];
              for (int a = 0; a < 3; ++a) o.stiffness[3 * r + a] -= ot.per_depth[r] * gk[1 + a];
            }
            if (o.source < 0) {
              o.source = t;
              const double dt = -gap(static_cast<std::size_t>(t))[0];
              for (int s = 0; s < 4; ++s) o.secant[s] = -gk[s] / dt;
            }
          }
    const double mean = 1.0 / std::max(used, 1);
    for (double& v : o.force) v *= mean;
    for (double& v : o.stiffness) v *= mean;
    for (double& v : o.per_depth) v *= mean;
  }
  return out;
}

}  // namespace hapstate::playback
