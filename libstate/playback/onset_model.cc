#include "playback/onset_model.h"

#include <algorithm>
#include <cstdlib>

namespace hapstate::playback {

std::vector<OnsetCorner> onset_corners(const Content& c) {
  const std::size_t n = c.config_checkpoint.size();
  std::vector<OnsetCorner> out(n, OnsetCorner{});
  for (OnsetCorner& o : out) o.source = -1;
  const double* h = c.meta.spacing;
  const double shallow = 1e-6 * std::min({h[0], h[1], h[2]});
  auto gap = [&](std::size_t config) {
    return &c.clearance[4 * static_cast<std::size_t>(c.config_checkpoint[config])];
  };
  for (std::size_t k = 0; k < n; ++k) {
    const double* gk = gap(k);
    OnsetCorner& o = out[k];
    if (c.config_zero[k] != 1 && -gk[0] >= shallow) {  // touching: q = f / d
      for (int r = 0; r < 3; ++r) o.per_depth[r] = c.force[3 * k + r] / -gk[0];
      o.has_depth_model = 1;
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double* gk = gap(k);
    // A free check-point's zero configuration, or a touching one at the onset itself (shallower
    // than `shallow`): q from the neighbours; only the former gets the secant model.
    const bool free = c.config_zero[k] == 1 && gk[0] >= 0.0;
    if (!free && !(c.config_zero[k] != 1 && gk[0] < 0.0 && -gk[0] < shallow)) continue;
    OnsetCorner& o = out[k];
    o.has_depth_model = 1;
    int used = 0;
    // Directions by grid distance (taxicab 1: straight, 2: face diagonal, 3: body diagonal),
    // numbered as in catalogue/direction.h; the nearest distance with a source is used.
    for (int dist = 1; dist <= 3 && used == 0; ++dist)
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk) {
            if (std::abs(di) + std::abs(dj) + std::abs(dk) != dist) continue;
            const int code = 9 * (di + 1) + 3 * (dj + 1) + (dk + 1);
            const int d = code < 13 ? code : code - 1;
            const std::int32_t t = c.transitions[26 * k + static_cast<std::size_t>(d)];
            if (t < 0 || static_cast<std::size_t>(t) >= n || c.config_zero[t] == 1) continue;
            const double* gt = gap(static_cast<std::size_t>(t));
            if (out[t].has_depth_model != 1 || -gt[0] < shallow) continue;
            ++used;
            for (int r = 0; r < 3; ++r) o.per_depth[r] += out[t].per_depth[r];
            if (!free) continue;
            const double* f = &c.force[3 * static_cast<std::size_t>(t)];
            for (int r = 0; r < 3; ++r) {
              o.force[r] += f[r] * gk[0] / gt[0];
              for (int a = 0; a < 3; ++a) o.stiffness[3 * r + a] += f[r] * gk[1 + a] / gt[0];
            }
            if (o.source < 0) {
              o.source = t;
              for (int s = 0; s < 4; ++s) o.secant[s] = gk[s] / gt[0];
            }
          }
    for (double& v : o.force) v /= std::max(used, 1);
    for (double& v : o.stiffness) v /= std::max(used, 1);
    for (double& v : o.per_depth) v /= std::max(used, 1);
  }
  return out;
}

}  // namespace hapstate::playback
