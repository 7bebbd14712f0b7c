// A synthetic playback file for the runtime tests: a 5 x 5 x 5 grid (anisotropic spacing)
// whose configurations carry an analytic force field f(P) and its exact Jacobian, one level
// each, every transition between neighbours stored, and displacements (with their slopes)
// that are a known function of the check-point. Edits (missing transitions) are applied by the
// tests.
#pragma once

#include "index/refined_cells.h"
#include "playback/writer.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <vector>

namespace hapstate::test_util {

// The field: linear part + smooth non-linear part, zero at the rest position.
struct Field {
  Eigen::Matrix3d a;
  double amplitude = 0.3;
  Eigen::Vector3d origin{1.0, 2.0, 3.0};

  Field() { a << -2.0, 0.3, 0.1, 0.3, -1.5, 0.2, 0.1, 0.2, -3.0; }
  Eigen::Vector3d raw(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d n(std::sin(x[0] + 2 * x[1]), std::cos(x[0] * x[2]) - 1.0,
                            x[0] * x[1] * x[2]);
    return a * x + amplitude * n;
  }
  Eigen::Vector3d force(const Eigen::Vector3d& p) const {
    return raw(p - origin) - raw(Eigen::Vector3d::Zero());
  }
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d x = p - origin;
    Eigen::Matrix3d n;
    const double c = std::cos(x[0] + 2 * x[1]), s = std::sin(x[0] * x[2]);
    n << c, 2 * c, 0, -s * x[2], 0, -s * x[0], x[1] * x[2], x[0] * x[2], x[0] * x[1];
    return a + amplitude * n;
  }
};

inline constexpr int kSyntheticViewNodes = 6;

// Displacement of view node v at check-point position P.
inline Eigen::Vector3d synthetic_displacement(const Field& field, int v, const Eigen::Vector3d& p) {
  return (0.1 * (v + 1)) * (p - field.origin) + 0.01 * field.force(p);
}

// Its derivative with respect to the probe position: column a = d u / d p_a.
inline Eigen::Matrix3d synthetic_displacement_slope(const Field& field, int v,
                                                    const Eigen::Vector3d& p) {
  return (0.1 * (v + 1)) * Eigen::Matrix3d::Identity() + 0.01 * field.jacobian(p);
}

// Content of the synthetic file with spacing h (grid indices -2..2 per axis; with flat_z only
// k = 0 along z: a planar workspace).
inline playback::Content synthetic_content(const Field& field, const Eigen::Vector3d& h,
                                           bool flat_z = false) {
  const int klo = flat_z ? 0 : -2, nk = flat_z ? 1 : 5;
  playback::Content c;
  playback::Meta& m = c.meta;
  for (int a = 0; a < 3; ++a) {
    m.origin[a] = field.origin[a];
    m.spacing[a] = h[a];
    m.rest_position[a] = field.origin[a];
    m.lo[a] = a == 2 ? klo : -2;
    m.dims[a] = a == 2 ? nk : 5;
  }
  m.max_force = 10.0;
  m.unit = 0.01;
  m.num_mesh_nodes = kSyntheticViewNodes;
  m.view_all_nodes = 1;
  auto position = [&](int i, int j, int k) {
    return Eigen::Vector3d(field.origin[0] + i * h[0], field.origin[1] + j * h[1],
                           field.origin[2] + k * h[2]);
  };
  auto index = [=](int i, int j, int k) { return ((i + 2) * 5 + (j + 2)) * nk + (k - klo); };
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      for (int k = klo; k < klo + nk; ++k) {
        const int g = index(i, j, k);
        c.checkpoints.push_back(g);
        c.checkpoints.push_back(1);
        c.config_checkpoint.push_back(g);
        c.config_level.push_back(0);
        c.config_zero.push_back(i == 0 && j == 0 && k == 0 ? 1 : 0);
        const Eigen::Vector3d p = position(i, j, k);
        const Eigen::Vector3d f = field.force(p);
        const Eigen::Matrix3d jac = field.jacobian(p);
        for (int r = 0; r < 3; ++r) c.force.push_back(f[r]);
        for (int r = 0; r < 3; ++r)
          for (int s = 0; s < 3; ++s) c.stiffness.push_back(jac(r, s));
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            for (int dk = -1; dk <= 1; ++dk) {
              if (di == 0 && dj == 0 && dk == 0) continue;
              const int ti = i + di, tj = j + dj, tk = k + dk;
              const bool inside =
                  std::abs(ti) <= 2 && std::abs(tj) <= 2 && tk >= klo && tk < klo + nk;
              c.transitions.push_back(inside ? index(ti, tj, tk) : playback::kOutsideGrid);
            }
      }
  m.rest_configuration = index(0, 0, 0);
  for (int v = 0; v < kSyntheticViewNodes; ++v) {
    c.view_nodes.push_back(v);
    for (int r = 0; r < 3; ++r) c.reference.push_back(static_cast<float>(v + r));
  }
  c.triangles = {0, 1, 2, 3, 4, 5};
  c.displacements = [field, h, position, nk, klo](std::int32_t config, std::span<float> out) {
    const int i = config / (5 * nk) - 2, j = (config / nk) % 5 - 2, k = config % nk + klo;
    for (int v = 0; v < kSyntheticViewNodes; ++v) {
      const Eigen::Vector3d u = synthetic_displacement(field, v, position(i, j, k));
      for (int r = 0; r < 3; ++r) out[3 * v + r] = static_cast<float>(u[r]);
    }
  };
  c.displacement_slopes = [field, h, position, nk, klo](std::int32_t config, std::span<float> out) {
    const int i = config / (5 * nk) - 2, j = (config / nk) % 5 - 2, k = config % nk + klo;
    for (int v = 0; v < kSyntheticViewNodes; ++v) {
      const Eigen::Matrix3d d = synthetic_displacement_slope(field, v, position(i, j, k));
      for (int a = 0; a < 3; ++a)
        for (int r = 0; r < 3; ++r)
          out[3 * (a * kSyntheticViewNodes + v) + r] = static_cast<float>(d(r, a));
    }
  };
  return c;
}

// Adds the force half-way through every move in the kMidpointOffsets directions (field.force
// there, for a Field or any type with that method; NaN where the move leaves the grid), as the
// expansion records it, and with `stiffness` the haptic stiffness there (field.jacobian).
template <class ForceField>
void add_midpoint_forces(playback::Content* c, const ForceField& field, bool stiffness = true) {
  const playback::Meta& m = c->meta;
  const std::size_t n = c->config_checkpoint.size();
  c->midpoint_force.assign(3 * playback::kMidpointDirections * n,
                           std::numeric_limits<double>::quiet_NaN());
  c->midpoint_stiffness.clear();
  if (stiffness)
    c->midpoint_stiffness.assign(9 * playback::kMidpointDirections * n,
                                 std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < n; ++k) {
    const int g = c->config_checkpoint[k];
    const int ijk[3] = {g / (m.dims[1] * m.dims[2]) + m.lo[0],
                        (g / m.dims[2]) % m.dims[1] + m.lo[1], g % m.dims[2] + m.lo[2]};
    for (int d = 0; d < playback::kMidpointDirections; ++d) {
      const int* o = playback::kMidpointOffsets[d];
      bool inside = true;
      Eigen::Vector3d p;
      for (int a = 0; a < 3; ++a) {
        inside = inside && ijk[a] + o[a] < m.lo[a] + m.dims[a];
        p[a] = m.origin[a] + (ijk[a] + 0.5 * o[a]) * m.spacing[a];
      }
      if (!inside) continue;
      const Eigen::Vector3d f = field.force(p);
      for (int r = 0; r < 3; ++r)
        c->midpoint_force[3 * (playback::kMidpointDirections * k + d) + r] = f[r];
      if (!stiffness) continue;
      const Eigen::Matrix3d jac = field.jacobian(p);
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a)
          c->midpoint_stiffness[9 * (playback::kMidpointDirections * k + d) + 3 * r + a] =
              jac(r, a);
    }
  }
}

// Adds the displacements u(node, p) and their slopes slope(node, p) (3 x 3, column a: d u / d p_a)
// half-way through every move in the kMidpointOffsets directions that stays in the grid, as the
// expansion records them (call after add_midpoint_forces: the cursor uses a midpoint's
// displacements only where it uses its force).
template <class Displacement, class Slope>
void add_midpoint_displacements(playback::Content* c, Displacement u_at, Slope slope_at) {
  const playback::Meta m = c->meta;
  const std::vector<std::int32_t> checkpoint = c->config_checkpoint;
  const std::size_t n = checkpoint.size();
  auto ijk_of = [m](int g) {
    return std::array<int, 3>{g / (m.dims[1] * m.dims[2]) + m.lo[0],
                              (g / m.dims[2]) % m.dims[1] + m.lo[1], g % m.dims[2] + m.lo[2]};
  };
  auto midpoint = [m, ijk_of](int g, int d, Eigen::Vector3d* p) {
    const auto ijk = ijk_of(g);
    const int* o = playback::kMidpointOffsets[d];
    for (int a = 0; a < 3; ++a) {
      if (ijk[a] + o[a] >= m.lo[a] + m.dims[a]) return false;
      (*p)[a] = m.origin[a] + (ijk[a] + 0.5 * o[a]) * m.spacing[a];
    }
    return true;
  };
  c->midpoint_displacement_mask.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k)
    for (int d = 0; d < playback::kMidpointDirections; ++d) {
      Eigen::Vector3d p;
      if (midpoint(checkpoint[k], d, &p)) c->midpoint_displacement_mask[k] |= 1 << d;
    }
  c->midpoint_displacements = [u_at, slope_at, checkpoint, midpoint](std::int32_t k,
                                                                     std::span<float> out) {
    constexpr int v = kSyntheticViewNodes;
    for (int d = 0; d < playback::kMidpointDirections; ++d) {
      Eigen::Vector3d p;
      if (!midpoint(checkpoint[k], d, &p)) continue;
      float* row = out.data() + 12 * v * d;
      for (int node = 0; node < v; ++node) {
        const Eigen::Vector3d u = u_at(node, p);
        const Eigen::Matrix3d s = slope_at(node, p);
        for (int r = 0; r < 3; ++r) {
          row[3 * node + r] = static_cast<float>(u[r]);
          for (int a = 0; a < 3; ++a)
            row[3 * ((1 + a) * v + node) + r] = static_cast<float>(s(r, a));
        }
      }
    }
  };
}

// The same with the synthetic displacements of `field` (synthetic_displacement).
inline void add_midpoint_displacements(playback::Content* c, const Field& field) {
  add_midpoint_displacements(
      c,
      [field](int node, const Eigen::Vector3d& p) {
        return synthetic_displacement(field, node, p);
      },
      [field](int node, const Eigen::Vector3d& p) {
        return synthetic_displacement_slope(field, node, p);
      });
}

// Refines the cells whose lowest corner is at each of `bases` (grid indices): the force and
// stiffness of `field` at every point of their quarter-spacing lattice the refine stage solves,
// and of the eighth-spacing one for those in `deep` (refinement depth 2), and of the sixteenth-
// spacing one in the eighth cells (64 i + 8 j + k) listed for a base in `sixteenth` (depth 3),
// through the index stage's add_refined_cells (which sets the constraint bits). `failed`: (base,
// catalogue point index) pairs whose solve failed. `per_cell`: the n-th base's forces are
// n x per_cell N above the field's in every component (two cells that solved a shared point to
// values a solver's tolerance apart). Call after add_midpoint_forces with stiffness.
template <class ForceField>
void add_refined_cells(
    playback::Content* c, const ForceField& field, const std::vector<std::array<int, 3>>& bases,
    const std::vector<std::pair<std::array<int, 3>, int>>& failed = {},
    const std::vector<std::array<int, 3>>& deep = {},
    const std::vector<std::pair<std::array<int, 3>, std::vector<int>>>& sixteenth = {},
    double per_cell = 0) {
  const playback::Meta& m = c->meta;
  std::vector<RefinementPoint> rows;
  std::map<std::int64_t, std::int32_t> index_of;
  for (std::size_t k = 0; k < c->config_checkpoint.size(); ++k)
    index_of.emplace(static_cast<std::int64_t>(k), static_cast<std::int32_t>(k));
  for (const auto& b : bases) {
    const int g = ((b[0] - m.lo[0]) * m.dims[1] + (b[1] - m.lo[1])) * m.dims[2] + (b[2] - m.lo[2]);
    const int config = c->checkpoints[2 * g];
    const bool is_deep = std::find(deep.begin(), deep.end(), b) != deep.end();
    std::set<int> finer;  // its sixteenth-spacing points
    for (const auto& [base, eighth_cells] : sixteenth)
      if (base == b)
        for (const int e : eighth_cells)
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              for (int k = 0; k < 3; ++k)
                finer.insert(kSixteenthFirstPoint + 289 * (2 * (e / 64) + i) +
                             17 * (2 * (e / 8 % 8) + j) + 2 * (e % 8) + k);
    std::vector<int> points;
    for (int p = 0; p < (is_deep ? 125 + 729 : 125); ++p) points.push_back(p);
    points.insert(points.end(), finer.begin(), finer.end());
    for (const int p : points) {
      const int n = p < 125 ? 5 : p < kSixteenthFirstPoint ? 9 : 17;
      const int e = p < 125 ? p : p < kSixteenthFirstPoint ? p - 125 : p - kSixteenthFirstPoint;
      const int q[3] = {e / (n * n), e / n % n, e % n};
      if (q[0] % 2 == 0 && q[1] % 2 == 0 && q[2] % 2 == 0) continue;
      Eigen::Vector3d x;
      for (int a = 0; a < 3; ++a) x[a] = m.origin[a] + (b[a] + q[a] / (n - 1.0)) * m.spacing[a];
      RefinementPoint row;
      row.cell = ConfigId(config);
      row.point = p;
      row.reached = std::find(failed.begin(), failed.end(), std::make_pair(b, p)) == failed.end();
      if (!row.reached) row.failure_reason = "failed on purpose (a test)";
      const Eigen::Vector3d f =
          field.force(x) + Eigen::Vector3d::Constant(per_cell * double(&b - bases.data()));
      const Eigen::Matrix3d jac = field.jacobian(x);
      for (int r = 0; r < 3; ++r) row.force[r] = f[r];
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) row.stiffness[3 * r + a] = jac(r, a);
      rows.push_back(row);
    }
  }
  hapstate::add_refined_cells(rows, index_of, c);
}

// `field` with a small smooth perturbation: refined points taken from it where the coarser
// interpolant belongs (a constraint missed) show as a jump of about 1e-3 N.
template <class ForceField>
struct Perturbed {
  const ForceField& f;
  Eigen::Vector3d force(const Eigen::Vector3d& p) const {
    return f.force(p) +
           1e-3 * Eigen::Vector3d(std::sin(3 * p[0]), std::cos(2 * p[1]), std::sin(p[2]));
  }
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& p) const {
    return f.jacobian(p) + Eigen::Vector3d(3e-3 * std::cos(3 * p[0]), -2e-3 * std::sin(2 * p[1]),
                                           1e-3 * std::cos(p[2]))
                               .asDiagonal()
                               .toDenseMatrix();
  }
};

// Grid direction index of offset (di, dj, dk) (catalogue/direction.h numbering).
inline int direction_of(int di, int dj, int dk) {
  const int c = 9 * (di + 1) + 3 * (dj + 1) + (dk + 1);
  return c < 13 ? c : c - 1;
}

}  // namespace hapstate::test_util
