// PRIVATE to the playback module: the arithmetic of one grid cell the cursor's rooms share
// (corner numbering, trilinear weights, the Hermite cell's coefficients and its contraction).
#pragma once

#include "playback/hermite_bases.h"
#include "util/grid_direction.h"

#include <array>
#include <cmath>
#include <cstdint>

namespace hapstate::playback {
// Internal linkage on purpose: each room gets its own copy, which the compiler inlines and
// specialises as it did when they were one file (as inline functions with external linkage the
// Hermite query measured 5-10 % slower: bench/cursor_ab.sh).
namespace {

using grid::direction_index;

// The axis pairs of the cross derivatives, in the order of their index.
constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};

inline std::array<std::int32_t, 3> corner_offset(int c) {
  return {(c >> 2) & 1, (c >> 1) & 1, c & 1};
}

// The trilinear scheme's bubble factors at cell position t (add_bubbles): the hat along a
// bubble's axes, the linear weights across them, and their derivatives per mesh unit.
inline void trilinear_bubble_bases(const std::array<double, 3>& t, const double* h, double (&m)[3],
                                   double (&dm)[3], double (&v)[3][2], double (&dv)[3][2]) {
  for (int a = 0; a < 3; ++a) {
    const double u = 1.0 - t[a];
    m[a] = t[a] < 0.5 ? 2.0 * t[a] : 2.0 * u;
    dm[a] = (t[a] < 0.5 ? 2.0 : -2.0) / h[a];
    v[a][0] = u, v[a][1] = t[a];
    dv[a][0] = -1.0 / h[a], dv[a][1] = 1.0 / h[a];
  }
}

// Corner c's trilinear weight at cell position t.
inline double trilinear_weight(int c, const std::array<double, 3>& t) {
  const auto o = corner_offset(c);
  return (o[0] ? t[0] : 1 - t[0]) * (o[1] ? t[1] : 1 - t[1]) * (o[2] ? t[2] : 1 - t[2]);
}

// A Hermite cell's value and its derivative (row-major, per mesh unit) at
// the point whose bases per axis are B (derivatives dB; hermite_bases): the tensor product of
// the coefficients [x][y][r][z] contracted axis by axis (z, then y, then x).
template <class Coefficients>
void hermite_contract(const Coefficients& coef, const double (&B)[3][4], const double (&dB)[3][4],
                      std::array<double, 3>* value, std::array<double, 9>* slope) {
  double A[4][4][3], Az[4][4][3];
  for (int ix = 0; ix < 4; ++ix)
    for (int iy = 0; iy < 4; ++iy)
      for (int r = 0; r < 3; ++r) {
        const std::array<double, 4>& t = coef[ix][iy][r];
        A[ix][iy][r] = B[2][0] * t[0] + B[2][1] * t[1] + B[2][2] * t[2] + B[2][3] * t[3];
        Az[ix][iy][r] = dB[2][0] * t[0] + dB[2][1] * t[1] + dB[2][2] * t[2] + dB[2][3] * t[3];
      }
  *value = {};
  *slope = {};
  for (int ix = 0; ix < 4; ++ix)
    for (int r = 0; r < 3; ++r) {
      double v = 0, vy = 0, vz = 0;
      for (int iy = 0; iy < 4; ++iy) {
        v += B[1][iy] * A[ix][iy][r];
        vy += dB[1][iy] * A[ix][iy][r];
        vz += B[1][iy] * Az[ix][iy][r];
      }
      (*value)[r] += B[0][ix] * v;
      (*slope)[3 * r] += dB[0][ix] * v;
      (*slope)[3 * r + 1] += B[0][ix] * vy;
      (*slope)[3 * r + 2] += B[0][ix] * vz;
    }
}

// The same at the 27 lattice points of the cell (cell positions 0, 1/2 and 1 per axis), axis by
// axis: value[x][y][z][r], gradient[x][y][z][3 r + a] and, if given, the cross derivatives
// cross[x][y][z][r][pair] (kPair).
template <class Coefficients>
void hermite_lattice(const Coefficients& coef, const double* h, double (&value)[3][3][3][3],
                     double (&gradient)[3][3][3][9], double (*cross)[3][3][3][3][3] = nullptr) {
  double B[3][3][4], dB[3][3][4];  // [axis][lattice index][basis]
  for (int i = 0; i < 3; ++i) {
    double b[3][4], db[3][4];
    hermite_bases({0.5 * i, 0.5 * i, 0.5 * i}, h, b, db);
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 4; ++k) B[a][i][k] = b[a][k], dB[a][i][k] = db[a][k];
  }
  double Z[4][4][3][3], dZ[4][4][3][3];  // [x][y][r][k]: z contracted
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int r = 0; r < 3; ++r) {
        const std::array<double, 4>& t = coef[x][y][r];
        for (int k = 0; k < 3; ++k) {
          Z[x][y][r][k] =
              B[2][k][0] * t[0] + B[2][k][1] * t[1] + B[2][k][2] * t[2] + B[2][k][3] * t[3];
          dZ[x][y][r][k] =
              dB[2][k][0] * t[0] + dB[2][k][1] * t[1] + dB[2][k][2] * t[2] + dB[2][k][3] * t[3];
        }
      }
  for (int j = 0; j < 3; ++j)
    for (int x = 0; x < 4; ++x)
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) {
          double v = 0, vy = 0, vz = 0, vyz = 0;  // y contracted: value, d/dy, d/dz, d2/dydz
          for (int y = 0; y < 4; ++y) {
            v += B[1][j][y] * Z[x][y][r][k];
            vy += dB[1][j][y] * Z[x][y][r][k];
            vz += B[1][j][y] * dZ[x][y][r][k];
            vyz += dB[1][j][y] * dZ[x][y][r][k];
          }
          for (int i = 0; i < 3; ++i) {
            if (x == 0) {
              value[i][j][k][r] = 0;
              for (int a = 0; a < 3; ++a) gradient[i][j][k][3 * r + a] = 0;
              if (cross)
                for (int q = 0; q < 3; ++q) (*cross)[i][j][k][r][q] = 0;
            }
            value[i][j][k][r] += B[0][i][x] * v;
            gradient[i][j][k][3 * r] += dB[0][i][x] * v;
            gradient[i][j][k][3 * r + 1] += B[0][i][x] * vy;
            gradient[i][j][k][3 * r + 2] += B[0][i][x] * vz;
            if (!cross) continue;
            (*cross)[i][j][k][r][0] += dB[0][i][x] * vy;
            (*cross)[i][j][k][r][1] += dB[0][i][x] * vz;
            (*cross)[i][j][k][r][2] += B[0][i][x] * vyz;
          }
        }
}

inline bool finite(const double* v, int n) {
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(v[k])) return false;
  return true;
}

// The Hermite coefficients [x][y][z] of a scalar with `value` and `gradient` (physical units)
// at the 8 corners: value (k = 000), gradient components (one k = 1), the cross derivatives
// `cross(c, a, b)` (k = 1 on axes a < b) and zero for k = 111. `at(kx, ky, kz)` is the
// coefficient of the basis with those indices (2 o + k per axis).
template <class Value, class Gradient, class Cross, class At>
void hermite_coefficients(Value value, Gradient gradient, Cross cross, At at) {
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    auto coef = [&](int kx, int ky, int kz) -> double& {
      return at(2 * o[0] + kx, 2 * o[1] + ky, 2 * o[2] + kz);
    };
    coef(0, 0, 0) = value(c);
    coef(1, 0, 0) = gradient(c, 0);
    coef(0, 1, 0) = gradient(c, 1);
    coef(0, 0, 1) = gradient(c, 2);
    for (const auto& pair : kPair) {
      int k[3] = {0, 0, 0};
      k[pair[0]] = k[pair[1]] = 1;
      coef(k[0], k[1], k[2]) = cross(c, pair[0], pair[1]);
    }
    coef(1, 1, 1) = 0.0;
  }
}

// The same with the cross derivatives estimated from the gradients of the corners on the same
// cell face (average of both difference quotients) and zero for k = 111.
template <class Value, class Gradient, class At>
void scalar_coefficients(const double* h, Value value, Gradient gradient, At at) {
  hermite_coefficients(
      value, gradient,
      [&](int c, int a, int b) {
        const auto o = corner_offset(c);
        auto sgn = [&](int axis) { return o[axis] ? 1.0 : -1.0; };
        const double dab = sgn(b) * (gradient(c, a) - gradient(c ^ (4 >> b), a)) / h[b];
        const double dba = sgn(a) * (gradient(c, b) - gradient(c ^ (4 >> a), b)) / h[a];
        return 0.5 * (dab + dba);
      },
      at);
}

// The derivative at lattice index i (0, 1, 2: cell positions 0, 1/2, 1) of the parabola through
// g0, g1, g2 at those indices, h the cell's spacing along the axis (second order everywhere).
inline double lattice_derivative(double g0, double g1, double g2, int i, double h) {
  if (i == 0) return (-3.0 * g0 + 4.0 * g1 - g2) / h;
  if (i == 1) return (g2 - g0) / h;
  return (g0 - 4.0 * g1 + 3.0 * g2) / h;
}

}  // namespace
}  // namespace hapstate::playback
