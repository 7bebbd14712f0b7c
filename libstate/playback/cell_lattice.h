// PRIVATE to the playback module: a cell's lattice of Hermite data (the half-spacing lattice of
// the midpoint fit, the quarter-spacing one of a refined cell) and its sub-cells' coefficients.
#pragma once

#include "playback/cell_math.h"
#include "playback/format.h"
#include "playback/lattice.h"

#include <algorithm>
#include <cstdint>

namespace hapstate::playback {
// Internal linkage on purpose: each room gets its own copy, which the compiler inlines and
// specialises as it did when they were one file (as inline functions with external linkage the
// Hermite query measured 5-10 % slower: bench/cursor_ab.sh).
namespace {

// Whether point (i, j, k) of a refined cell's lattice with `last` + 1 points per axis lies on a
// face or an edge set in `constraints` (playback/format.h bits).
inline bool constrained(const int (&p)[3], int last, std::int32_t constraints) {
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      if (p[a] != last * side) continue;
      if (constraints >> playback::refined_face_bit(a, side) & 1) return true;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      // the edges along b and along c on this face
      for (int s2 = 0; s2 < 2; ++s2) {
        // along b: sides of c (next of b) and a (next of c)
        if (p[c] == last * s2 && (constraints >> playback::refined_edge_bit(b, s2, side) & 1))
          return true;
        // along c: sides of a (next of c) and b
        if (p[b] == last * s2 && (constraints >> playback::refined_edge_bit(c, side, s2) & 1))
          return true;
      }
    }
  return false;
}

// The cross derivatives at point (x, y, z) of L: along each lattice line, the slope of the
// parabola through 3 neighbouring gradients (second order, where differences between 2 points
// are first order). Those in a face's plane use only that face's points: the force stays
// continuous. Zero for the triple derivative, as in the corners' cubic. h: the cell's spacing.
template <int N>
void lattice_point_cross(const double* h, Lattice<N>* L, int x, int y, int z) {
  const int p[3] = {x, y, z};
  auto along = [&](int axis, int component) {
    const int first = std::clamp(p[axis] - 1, 0, N - 3);
    int q[3] = {p[0], p[1], p[2]};
    double g[3];
    for (int i = 0; i < 3; ++i) {
      q[axis] = first + i;
      g[i] = L->gradient[q[0]][q[1]][q[2]][component];
    }
    return lattice_derivative(g[0], g[1], g[2], p[axis] - first, 2.0 * h[axis] / (N - 1));
  };
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) {
      const int a = kPair[q][0], b = kPair[q][1];
      L->cross[x][y][z][r][q] = 0.5 * (along(b, 3 * r + a) + along(a, 3 * r + b));
    }
}

// The cross derivatives at every point of L but those where `keep` is true
// (lattice_point_cross).
template <int N>
void lattice_cross(const double* h, Lattice<N>* L, const bool (*keep)[N][N] = nullptr) {
  for (int x = 0; x < N; ++x)
    for (int y = 0; y < N; ++y)
      for (int z = 0; z < N; ++z)
        if (!keep || !keep[x][y][z]) lattice_point_cross(h, L, x, y, z);
}

// A Hermite cell's value, gradient (row-major) and cross derivatives [r][pair] (kPair) at cell
// position t (the lattice's data at one point; hermite_lattice at 27 at once).
template <class Coefficients>
void hermite_point(const Coefficients& coef, const double* h, const std::array<double, 3>& t,
                   double* value, double* gradient, double (*cross)[3]) {
  double B[3][4], dB[3][4];
  hermite_bases(t, h, B, dB);
  for (int r = 0; r < 3; ++r) {
    value[r] = 0;
    for (int a = 0; a < 3; ++a) gradient[3 * r + a] = 0, cross[r][a] = 0;
  }
  for (int ix = 0; ix < 4; ++ix)
    for (int r = 0; r < 3; ++r) {
      double v = 0, vy = 0, vz = 0, vyz = 0;  // y and z contracted
      for (int iy = 0; iy < 4; ++iy) {
        const std::array<double, 4>& c = coef[ix][iy][r];
        const double w = B[2][0] * c[0] + B[2][1] * c[1] + B[2][2] * c[2] + B[2][3] * c[3];
        const double dw = dB[2][0] * c[0] + dB[2][1] * c[1] + dB[2][2] * c[2] + dB[2][3] * c[3];
        v += B[1][iy] * w;
        vy += dB[1][iy] * w;
        vz += B[1][iy] * dw;
        vyz += dB[1][iy] * dw;
      }
      value[r] += B[0][ix] * v;
      gradient[3 * r] += dB[0][ix] * v;
      gradient[3 * r + 1] += B[0][ix] * vy;
      gradient[3 * r + 2] += B[0][ix] * vz;
      cross[r][0] += dB[0][ix] * vy;
      cross[r][1] += dB[0][ix] * vz;
      cross[r][2] += B[0][ix] * vyz;
    }
}

// The Hermite coefficients of sub-cell `sub` of L, (x, y, z) at (x (N - 1) + y) (N - 1) + z,
// from the data at its 8 lattice points.
template <int N, class Coefficients>
void sub_cell_coefficient(const Lattice<N>& L, int sub, Coefficients* out) {
  const int so[3] = {sub / ((N - 1) * (N - 1)), sub / (N - 1) % (N - 1), sub % (N - 1)};
  auto point = [&](int c) {
    const auto o = corner_offset(c);
    return std::array<int, 3>{so[0] + o[0], so[1] + o[1], so[2] + o[2]};
  };
  for (int r = 0; r < 3; ++r)
    hermite_coefficients(
        [&](int c) {
          const auto p = point(c);
          return L.value[p[0]][p[1]][p[2]][r];
        },
        [&](int c, int a) {
          const auto p = point(c);
          return L.gradient[p[0]][p[1]][p[2]][3 * r + a];
        },
        [&](int c, int a, int b) {
          const auto p = point(c);
          return L.cross[p[0]][p[1]][p[2]][r][a + b - 1];
        },
        [&](int x, int y, int z) -> double& { return (*out)[x][y][r][z]; });
}

// The Hermite coefficients of the (N - 1)^3 sub-cells of L (sub_cell_coefficient).
template <int N, class Coefficients>
void sub_cell_coefficients(const Lattice<N>& L, Coefficients* out) {
  for (int sub = 0; sub < (N - 1) * (N - 1) * (N - 1); ++sub)
    sub_cell_coefficient(L, sub, &out[sub]);
}

}  // namespace
}  // namespace hapstate::playback
