#include "playback/onset_model.h"

#include "playback/depth_model.h"

#include "util/grid_direction.h"
#include "util/triangle_point.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace hapstate::playback {

std::vector<OnsetCorner> onset_corners(const Content& c) {
  const std::size_t n = c.config_checkpoint.size();
  std::vector<OnsetCorner> out(n, OnsetCorner{});
  const double* h = c.meta.spacing;
  const double shallow = shallow_depth(h);
  const double band = onset_band(h);
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
    depth_model(&c.force[3 * k], &c.stiffness[9 * k], g, band, o.per_depth, o.per_depth_squared);
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

void add_onset_triangles(Content* content, const std::vector<double>& triangles, double radius) {
  Content& c = *content;
  const Meta& m = c.meta;
  const double* h = m.spacing;
  const double band = onset_band(h);
  if (!(radius >= 1.5 * band) || triangles.empty()) return;
  const double diagonal = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  const std::size_t count = triangles.size() / 9;
  auto corner = [&](std::size_t t, int i) {
    return Eigen::Vector3d(triangles[9 * t + 3 * i], triangles[9 * t + 3 * i + 1],
                           triangles[9 * t + 3 * i + 2]);
  };
  const std::int64_t points = std::int64_t(m.dims[0]) * m.dims[1] * m.dims[2];
  std::vector<std::int32_t> index_of(count, -1);  // triangle -> its index in section 24
  std::vector<double> distance(count);
  c.onset_cells.assign(1, 0);
  for (std::int64_t g = 0; g < points; ++g) {
    const std::array<std::int32_t, 3> ijk = grid_point_ijk(m, g);
    // The cell whose lowest corner g is; along an axis with one check-point it is flat.
    bool cell = true;
    double shallowest = std::numeric_limits<double>::infinity(), deepest = -shallowest;
    Eigen::Vector3d centre;
    for (int a = 0; a < 3; ++a) {
      const bool flat = m.dims[a] == 1;
      cell = cell && (flat || ijk[a] < m.lo[a] + m.dims[a] - 1);
      centre[a] = m.origin[a] + (ijk[a] + (flat ? 0.0 : 0.5)) * h[a];
    }
    if (cell)
      for (int k = 0; k < 8; ++k) {
        std::array<std::int32_t, 3> q = ijk;
        for (int a = 0; a < 3; ++a)
          if (m.dims[a] > 1) q[a] += (k >> (2 - a)) & 1;
        const double depth = -c.clearance[4 * std::size_t(grid_point_index(m, q))];
        shallowest = std::min(shallowest, depth);
        deepest = std::max(deepest, depth);
      }
    const OnsetCellTest test = cell ? onset_cell_test(shallowest, deepest, h) : OnsetCellTest{};
    if (test.blend && !test.clear) {
      // Any point p of the cell is within half a diagonal of the centre, so its nearest triangle
      // is within the centre's nearest distance plus a diagonal of the centre; and where that
      // triangle is nearer than the radius (the sphere touches), within the radius plus half a
      // diagonal. Farther points measure more than the radius from the list: clear, as they are.
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t t = 0; t < count; ++t) {
        distance[t] = closest_point(corner(t, 0), corner(t, 1), corner(t, 2), centre).distance;
        nearest = std::min(nearest, distance[t]);
      }
      const double reach = std::min(nearest + diagonal, radius + 0.5 * diagonal) * (1.0 + 1e-9);
      for (std::size_t t = 0; t < count; ++t) {
        if (distance[t] > reach) continue;
        if (index_of[t] < 0) {
          index_of[t] = static_cast<std::int32_t>(c.onset_triangles.size() / 9);
          c.onset_triangles.insert(c.onset_triangles.end(), triangles.begin() + 9 * t,
                                   triangles.begin() + 9 * t + 9);
        }
        c.onset_triangle_list.push_back(index_of[t]);
      }
    }
    c.onset_cells.push_back(static_cast<std::int32_t>(c.onset_triangle_list.size()));
  }
  if (c.onset_triangle_list.empty()) {
    c.onset_cells.clear();
    c.onset_triangles.clear();
    return;
  }
  c.meta.contact_radius = radius;
}

}  // namespace hapstate::playback
