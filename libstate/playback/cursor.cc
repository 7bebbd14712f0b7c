// HapticCursor: the cell walk, corner resolution and the two interpolation schemes
// (docs/playback.md). Nothing here allocates, locks or calls the system after construction.
#include "playback/cell_bubbles.h"
#include "playback/file_impl.h"
#include "playback/hermite_bases.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapstate {
namespace {

using playback::hermite_bases;

// The axis pairs of the cross derivatives, in the order of their index.
constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};

// The band above the contact onset, in units of the smallest spacing, over which the force
// blends from the depth model into the interpolated force (apply_onset).
constexpr double kOnsetBand = 0.5;

constexpr std::uint32_t kFresh = 4;  // triple buffer: the middle slot holds an unread snapshot

std::array<std::int32_t, 3> corner_offset(int c) { return {(c >> 2) & 1, (c >> 1) & 1, c & 1}; }

// The trilinear scheme's bubble factors at cell position t (add_bubbles): the hat along a
// bubble's axes, the linear weights across them, and their derivatives per mesh unit.
void trilinear_bubble_bases(const std::array<double, 3>& t, const double* h, double (&m)[3],
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
double trilinear_weight(int c, const std::array<double, 3>& t) {
  const auto o = corner_offset(c);
  return (o[0] ? t[0] : 1 - t[0]) * (o[1] ? t[1] : 1 - t[1]) * (o[2] ? t[2] : 1 - t[2]);
}

// Direction index (catalogue/direction.h numbering) of grid offset (di, dj, dk).
int direction_index(int di, int dj, int dk) {
  const int c = 9 * (di + 1) + 3 * (dj + 1) + (dk + 1);
  return c < 13 ? c : c - 1;
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

bool finite(const double* v, int n) {
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(v[k])) return false;
  return true;
}

}  // namespace

HapticCursor::HapticCursor(const PlaybackFile& file, Scheme scheme) : file_(file), scheme_(scheme) {
  reset();
}

void HapticCursor::reset() { anchor_at(file_.impl().meta->rest_configuration); }

void HapticCursor::reset(const std::array<double, 3>& probe) {
  const PlaybackFile::Impl& f = file_.impl();
  const playback::Meta& m = *f.meta;
  std::int32_t best = m.rest_configuration;
  double best_d2 = -1.0;
  for (std::int32_t c = 0; c < m.num_configurations; ++c) {
    if (f.config_zero[c] != 1) continue;
    const auto ijk = f.point_ijk(f.config_checkpoint[c]);
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double d = m.origin[a] + ijk[a] * m.spacing[a] - probe[a];
      d2 += d * d;
    }
    if (std::isfinite(d2) && (best_d2 < 0.0 || d2 < best_d2)) best = c, best_d2 = d2;
  }
  anchor_at(best);
}

// Configuration t as a cell corner: its force, stiffness and displacements, and in a contact
// file its onset data (playback/format.h, OnsetCorner; indices out of range: none).
HapticCursor::Corner HapticCursor::stored_corner(std::int32_t t) const {
  const PlaybackFile::Impl& f = file_.impl();
  Corner r;
  r.configuration = t;
  r.displacement = t;
  r.source = CornerSource::kStored;
  std::copy_n(f.force + 3 * std::int64_t(t), 3, r.force.begin());
  std::copy_n(f.stiffness + 9 * std::int64_t(t), 9, r.stiffness.begin());
  if (!f.onset) return r;
  const playback::OnsetCorner& o = f.onset[t];
  auto valid = [&](std::int32_t k) { return k >= 0 && k < f.meta->num_configurations; };
  r.onset = &o;
  r.secant = valid(o.source);
  r.depth_model = valid(o.depth_source);
  return r;
}

// The cursor at the check-point of configuration `rest` (a zero configuration), that corner
// from it and the others resolved around it.
void HapticCursor::anchor_at(std::int32_t rest) {
  const PlaybackFile::Impl& f = file_.impl();
  const playback::Meta& m = *f.meta;
  const std::array<std::int32_t, 3> ijk = f.point_ijk(f.config_checkpoint[rest]);
  Corner root = stored_corner(rest);
  if (!finite(root.force.data(), 3) || !finite(root.stiffness.data(), 9)) {
    root.force = {};
    root.stiffness = {};
  }
  // A one-corner "old cell" holding the rest corner, then resolve the cell around it.
  std::array<Corner, 8> old{};
  std::array<std::int32_t, 3> base{};
  for (int a = 0; a < 3; ++a) base[a] = std::clamp(ijk[a], m.lo[a], f.last_cell(a));
  int rest_corner = 0;
  for (int a = 0; a < 3; ++a) rest_corner |= (ijk[a] - base[a]) << (2 - a);
  for (int c = 0; c < 8; ++c) old[c].source = CornerSource::kExtended, old[c].configuration = -2;
  old[rest_corner] = root;
  base_ = base;
  corners_ = old;
  for (int c = 0; c < 8; ++c)
    if (c != rest_corner) resolve_corner(c, old, base);
  update_coefficients();
  for (int a = 0; a < 3; ++a) last_q_[a] = ijk[a];
  calls_ = 0;
  cells_walked_ = 0;
  Force zero;
  std::array<double, 3> s{};
  for (int a = 0; a < 3; ++a) s[a] = ijk[a] - base_[a];
  std::array<double, 3> p{};
  for (int a = 0; a < 3; ++a) p[a] = m.origin[a] + ijk[a] * m.spacing[a];
  // The stored force there (a zero configuration beside the contact onset holds the onset model
  // as a corner, but the sphere is clear of the body at its check-point).
  std::copy_n(f.force + 3 * std::int64_t(rest), 3, zero.value.begin());
  std::copy_n(f.stiffness + 9 * std::int64_t(rest), 9, zero.stiffness.begin());
  if (!finite(zero.value.data(), 3) || !finite(zero.stiffness.data(), 9)) zero = Force{};
  OnsetBlend rest_state;  // a zero configuration: the body at rest
  rest_state.at_rest = true;
  publish(p, zero, s, rest_state);
}

// Fills corners_[c] of the cell at base_ from the corners of the previous cell `old` (at
// old_base) that it shares: a stored transition from a shared stored corner (the straight
// neighbour first), else an extension of the nearest shared corner. Shared corners were copied.
void HapticCursor::resolve_corner(int c, const std::array<Corner, 8>& old,
                                  const std::array<std::int32_t, 3>& old_base) {
  const PlaybackFile::Impl& f = file_.impl();
  const auto oc = corner_offset(c);
  std::array<std::int32_t, 3> target{};
  for (int a = 0; a < 3; ++a) target[a] = base_[a] + oc[a];
  // Candidate sources: old corners that are grid neighbours of the target (all corners of two
  // adjacent cells are), nearest first (taxicab), then by corner number.
  int order[8];
  int count = 0;
  for (int dist = 1; dist <= 3; ++dist)
    for (int k = 0; k < 8; ++k) {
      if (old[k].configuration == -2) continue;  // not a corner of the old cell (reset)
      const auto ok = corner_offset(k);
      int t = 0;
      bool neighbour = true;
      for (int a = 0; a < 3; ++a) {
        const int d = target[a] - (old_base[a] + ok[a]);
        neighbour = neighbour && d >= -1 && d <= 1;
        t += d < 0 ? -d : d;
      }
      if (neighbour && t == dist) order[count++] = k;
    }
  Corner& out = corners_[c];
  for (int n = 0; n < count; ++n) {
    const Corner& src = old[order[n]];
    if (src.configuration < 0) continue;
    const auto ok = corner_offset(order[n]);
    const int d = direction_index(target[0] - old_base[0] - ok[0], target[1] - old_base[1] - ok[1],
                                  target[2] - old_base[2] - ok[2]);
    const std::int32_t t = f.transition(src.configuration, d);
    if (t < 0) continue;
    const Corner r = stored_corner(t);
    if (!finite(r.force.data(), 3) || !finite(r.stiffness.data(), 9)) continue;
    out = r;
    return;
  }
  // Extended: first-order Taylor from the nearest shared corner, f + K (P - P_src).
  const Corner& src = old[order[0]];
  const auto ok = corner_offset(order[0]);
  const double* h = f.meta->spacing;
  Corner e;
  e.configuration = -1;
  e.displacement = src.displacement;
  for (int a = 0; a < 3; ++a) e.shift[a] = src.shift[a] + target[a] - old_base[a] - ok[a];
  e.source = CornerSource::kExtended;
  e.stiffness = src.stiffness;
  for (int r = 0; r < 3; ++r) {
    double v = src.force[r];
    for (int a = 0; a < 3; ++a)
      v += src.stiffness[3 * r + a] * (target[a] - old_base[a] - ok[a]) * h[a];
    e.force[r] = v;
  }
  out = e;
}

namespace {

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
double lattice_derivative(double g0, double g1, double g2, int i, double h) {
  if (i == 0) return (-3.0 * g0 + 4.0 * g1 - g2) / h;
  if (i == 1) return (g2 - g0) / h;
  return (g0 - 4.0 * g1 + 3.0 * g2) / h;
}

}  // namespace

// Contact: whether the cell blends in the depth model near the onset (every corner has one,
// so no corner is extended or touching while clear of the rest body, and some corner is within
// the band plus a cell diagonal of the onset: the clearance changes by at most the distance);
// the clearance's Hermite coefficients.
void HapticCursor::prepare_onset() {
  const PlaybackFile::Impl& f = file_.impl();
  onset_ = false;
  if (!f.clearance) return;
  const double* h = f.meta->spacing;
  // Along an axis with one check-point the cell is flat (s = 0): its far corners weigh nothing
  // and take the data of their partners on the grid.
  int flat = 0;
  for (int a = 0; a < 3; ++a) flat |= f.meta->dims[a] == 1 ? 4 >> a : 0;
  double gap[8][4];
  double shallowest = std::numeric_limits<double>::infinity(), deepest = -shallowest;
  for (int c = 0; c < 8; ++c) {
    if (!corners_[c & ~flat].depth_model) return;
    std::copy_n(corners_[c & ~flat].onset->per_depth, 3, per_depth_[c].begin());
    const auto o = corner_offset(c);
    std::array<std::int32_t, 3> ijk{};
    for (int a = 0; a < 3; ++a)
      ijk[a] = std::min(base_[a] + o[a], f.meta->lo[a] + f.meta->dims[a] - 1);
    const std::int32_t g = f.point_index(ijk);
    if (g < 0) return;
    for (int k = 0; k < 4; ++k) gap[c][k] = f.clearance[4 * std::int64_t(g) + k];
    shallowest = std::min(shallowest, -gap[c][0]);
    deepest = std::max(deepest, -gap[c][0]);
  }
  const double diagonal = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  if (shallowest > kOnsetBand * std::min({h[0], h[1], h[2]}) + diagonal) return;
  onset_ = true;
  // Every point of the cell is within a diagonal of every corner and the clearance changes by
  // at most the distance: clear by a diagonal at every corner, the sphere is clear of the rest
  // body in the whole cell (and so is the interpolated clearance).
  clear_cell_ = -deepest >= diagonal;
  scalar_coefficients(
      h, [&](int c) { return gap[c][0]; }, [&](int c, int a) { return gap[c][1 + a]; },
      [&](int x, int y, int z) -> double& { return clearance_coef_[x][y][z]; });
}

// The interpolated clearance (Hermite) and its gradient `grad` per mesh unit at the point
// whose bases per axis are B (derivatives dB; both as in force()).
double HapticCursor::clearance(const double (&B)[3][4], const double (&dB)[3][4],
                               double (&grad)[3]) const {
  double g = 0;
  grad[0] = grad[1] = grad[2] = 0;
  // The tensor product contracted axis by axis (z, then y, then x).
  for (int x = 0; x < 4; ++x) {
    double v = 0, vy = 0, vz = 0;
    for (int y = 0; y < 4; ++y) {
      const std::array<double, 4>& t = clearance_coef_[x][y];
      const double a = B[2][0] * t[0] + B[2][1] * t[1] + B[2][2] * t[2] + B[2][3] * t[3];
      const double az = dB[2][0] * t[0] + dB[2][1] * t[1] + dB[2][2] * t[2] + dB[2][3] * t[3];
      v += B[1][y] * a;
      vy += dB[1][y] * a;
      vz += B[1][y] * az;
    }
    g += B[0][x] * v;
    grad[0] += dB[0][x] * v;
    grad[1] += B[0][x] * vy;
    grad[2] += B[0][x] * vz;
  }
  return g;
}

// Near the contact onset: with d the interpolated depth of the sphere into the rest body
// (Hermite, from the clearance at the corners), the force is 0 where d <= 0 and
// R F + (1 - R) d q for 0 < d < band, F the interpolated force, q the trilinear interpolation of
// the corners' force per unit depth and R = smoothstep(d / band): continuous at the onset and at
// the band's edge, exact at check-points (q d = f there) and for a force proportional to the
// depth. `value` and `slope` hold F and its derivative on entry.
HapticCursor::OnsetBlend HapticCursor::apply_onset(const double (&B)[3][4],
                                                   const double (&dB)[3][4],
                                                   const std::array<double, 3>& s,
                                                   std::array<double, 3>* value,
                                                   std::array<double, 9>* slope) const {
  const double* h = file_.impl().meta->spacing;
  OnsetBlend blend;
  double grad[3] = {0, 0, 0};
  const double g = clear_cell_ ? 0.0 : clearance(B, dB, grad);
  blend.depth = -g;
  if (clear_cell_ || blend.depth <= 0.0) {
    *value = {};
    *slope = {};
    blend.at_rest = true;
    return blend;
  }
  const double band = kOnsetBand * std::min({h[0], h[1], h[2]});
  if (blend.depth >= band) return blend;
  double q[3], dq[3][3];
  per_depth_at(s, q, dq);
  const double x = blend.depth / band;
  const double R = x * x * (3.0 - 2.0 * x), dR = 6.0 * x * (1.0 - x) / band;  // dR / d(depth)
  for (int r = 0; r < 3; ++r) {
    const double model = blend.depth * q[r];
    for (int a = 0; a < 3; ++a) {
      const double dmodel = -q[r] * grad[a] + blend.depth * dq[r][a];
      (*slope)[3 * r + a] =
          R * (*slope)[3 * r + a] + (1.0 - R) * dmodel - ((*value)[r] - model) * dR * grad[a];
    }
    (*value)[r] = R * (*value)[r] + (1.0 - R) * model;
  }
  blend.weight = 1.0 - R;
  return blend;
}

// The corners' force per unit depth q, interpolated trilinearly at cell position t, and its
// derivative dq[r][a] per mesh unit.
void HapticCursor::per_depth_at(const std::array<double, 3>& t, double (&q)[3],
                                double (&dq)[3][3]) const {
  const double* h = file_.impl().meta->spacing;
  for (int r = 0; r < 3; ++r) q[r] = dq[r][0] = dq[r][1] = dq[r][2] = 0.0;
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    const double w[3] = {o[0] ? t[0] : 1.0 - t[0], o[1] ? t[1] : 1.0 - t[1],
                         o[2] ? t[2] : 1.0 - t[2]};
    const double dw[3] = {(o[0] ? 1.0 : -1.0) / h[0] * w[1] * w[2],
                          (o[1] ? 1.0 : -1.0) / h[1] * w[0] * w[2],
                          (o[2] ? 1.0 : -1.0) / h[2] * w[0] * w[1]};
    for (int r = 0; r < 3; ++r) {
      q[r] += w[0] * w[1] * w[2] * per_depth_[c][r];
      for (int a = 0; a < 3; ++a) dq[r][a] += dw[a] * per_depth_[c][r];
    }
  }
}

// The onset blend at cell position t where a midpoint may be fitted through it: R, dR/d(depth),
// the depth and the clearance's gradient (the depth's, negated). False where the cell is clear of
// the body, the depth is not positive or R < 1/4 (the blend barely follows F there, and a free
// midpoint's 0 would bend the secant field): the midpoint is left out there.
bool HapticCursor::onset_blend_at(const std::array<double, 3>& t, OnsetPoint* out) const {
  if (clear_cell_) return false;
  const double* h = file_.impl().meta->spacing;
  double B[3][4], dB[3][4];
  hermite_bases(t, h, B, dB);
  out->depth = -clearance(B, dB, out->grad);
  if (!(out->depth > 0.0)) return false;
  const double band = kOnsetBand * std::min({h[0], h[1], h[2]});
  const double x = std::min(out->depth / band, 1.0);
  out->R = x * x * (3.0 - 2.0 * x);
  out->dR = 6.0 * x * (1.0 - x) / band;
  return out->R >= 0.25;
}

// The interpolated force F at cell position t, where the onset blend is o (onset_blend_at
// true), for which the blend (apply_onset) returns `felt`: (felt - (1 - R) d q) / R, and, if
// `felt_k` is given, the derivative of F for which the blend's derivative is felt_k (row-major,
// per mesh unit): (felt_k - (1 - R) d(d q)/dp + (F - d q) R' grad d^T) / R. False where they
// are not finite.
bool HapticCursor::onset_target(const std::array<double, 3>& t, const OnsetPoint& o,
                                const double* felt, const double* felt_k, double* out,
                                double* out_k) const {
  const double R = o.R, dR = o.dR, depth = o.depth;
  const double* grad = o.grad;
  double q[3], dq[3][3];
  per_depth_at(t, q, dq);
  for (int r = 0; r < 3; ++r) out[r] = (felt[r] - (1.0 - R) * depth * q[r]) / R;
  if (felt_k)
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) {
        const double dmodel = -q[r] * grad[a] + depth * dq[r][a];
        out_k[3 * r + a] =
            (felt_k[3 * r + a] - (1.0 - R) * dmodel + (out[r] - depth * q[r]) * dR * grad[a]) / R;
      }
  return finite(out, 3) && (!felt_k || finite(out_k, 9));
}

const double* HapticCursor::force_of(int c) const {
  return onset_ && corners_[c].secant ? corners_[c].onset->force : corners_[c].force.data();
}
const double* HapticCursor::stiffness_of(int c) const {
  return onset_ && corners_[c].secant ? corners_[c].onset->stiffness : corners_[c].stiffness.data();
}

// The Hermite coefficients of the current cell's force: per component, each corner's force and
// stiffness row.
void HapticCursor::update_coefficients() {
  prepare_onset();
  coef_ = {};
  for (int r = 0; r < 3; ++r)
    scalar_coefficients(
        file_.impl().meta->spacing, [&](int c) { return force_of(c)[r]; },
        [&](int c, int a) { return stiffness_of(c)[3 * r + a]; },
        [&](int x, int y, int z) -> double& { return coef_[x][y][r][z]; });
  fitted_ = false;         // the midpoint data are fitted at the first force() in this cell
  midpoint_code_.fill(0);  // (and found then: a snapshot before shows the corners' cubic)
  midpoint_blend_ = {};
  ++blend_generation_;
}

static_assert(playback::kCellBubbles == 19, "HapticCursor::bubble_ holds one per bubble");

// What the corners' moves recorded at bubble k's point (an edge midpoint, a face or the cell
// centre): 0 nothing, 1 the force (into `force`), 2 the force and the stiffness (into
// `stiffness`, row-major). A value is used when both corners of its move are stored
// configurations and the source's move in that direction leads to the target corner's
// configuration (the recorded value belongs to the corners the cell shows).
int HapticCursor::recorded_midpoint(int k, double* force, double* stiffness) const {
  const PlaybackFile::Impl& f = file_.impl();
  if (!f.midpoint_force) return 0;
  const playback::BubbleSpec b = playback::bubble_spec(k);
  const std::int32_t source = corners_[b.source_corner].configuration;
  const std::int32_t target = corners_[b.target_corner].configuration;
  if (source < 0 || target < 0) return 0;
  const int* o = playback::kMidpointOffsets[b.direction];
  if (f.transition(source, direction_index(o[0], o[1], o[2])) != target) return 0;
  const std::int64_t at = playback::kMidpointDirections * std::int64_t(source) + b.direction;
  const double* m = f.midpoint_force + 3 * at;
  if (!finite(m, 3)) return 0;
  std::copy_n(m, 3, force);
  if (!f.midpoint_stiffness || !finite(f.midpoint_stiffness + 9 * at, 9)) return 1;
  std::copy_n(f.midpoint_stiffness + 9 * at, 9, stiffness);
  return 2;
}

// What the cell's fit aims at midpoint k: the recorded force and stiffness, or in a cell near the
// contact onset those the blend turns into them (onset_target), where that blend allows a fit
// (onset_blend_at, kept for the displacements). Computed once per cell entry.
struct HapticCursor::MidpointTarget {
  int recorded = 0;       // recorded_midpoint: 0 none, 1 the force, 2 force and stiffness
  bool fitted = false;    // force (and with recorded == 2 stiffness) below are valid
  bool force_ok = false;  // force below is valid (what the bubbles need)
  double force[3] = {};   // N
  double stiffness[9] = {};
  bool in_blend = false;  // near the onset: onset_blend_at allows a fit at the point
  OnsetPoint onset;       // and the blend there
};

void HapticCursor::midpoint_target(int k, MidpointTarget* out) const {
  double felt[3], felt_k[9];
  out->recorded = recorded_midpoint(k, felt, felt_k);
  if (out->recorded == 0) return;
  const bool with_k = out->recorded == 2;
  if (!onset_) {
    std::copy_n(felt, 3, out->force);
    if (with_k) std::copy_n(felt_k, 9, out->stiffness);
    out->fitted = out->force_ok = true;
    return;
  }
  const std::array<double, 3>& point = playback::bubble_spec(k).point;
  out->in_blend = onset_blend_at(point, &out->onset);
  if (!out->in_blend) return;
  out->fitted =
      onset_target(point, out->onset, felt, with_k ? felt_k : nullptr, out->force, out->stiffness);
  out->force_ok = finite(out->force, 3);
}

void HapticCursor::fit_cell() {
  fitted_ = true;
  refined_ = false;
  num_bubbles_ = 0;
  MidpointTarget targets[playback::kCellBubbles];
  for (int k = 0; k < playback::kCellBubbles; ++k) midpoint_target(k, &targets[k]);
  find_midpoint_displacements(targets);
  lattice_ = scheme_ == Scheme::kHermite && file_.impl().midpoint_stiffness;
  if (lattice_) {
    fit_cell_lattice(targets);
  } else {
    fit_cell_bubbles(targets);
    if (scheme_ == Scheme::kTrilinear) {
      const std::int32_t slot = refined_cell();
      if (slot >= 0) fit_refined_trilinear(slot);
    }
  }
}

// The midpoints of this cell whose displacements deform() uses (Snapshot::midpoint): those
// whose force the cursor uses (recorded_midpoint) and whose displacements the file holds; in a
// cell near the contact onset, those where the force's fit may use the blend (onset_blend_at),
// with the blend at the point (Snapshot::midpoint_blend) through which deform() fits them.
void HapticCursor::find_midpoint_displacements(const MidpointTarget* targets) {
  const PlaybackFile::Impl& f = file_.impl();
  midpoint_code_.fill(0);
  midpoint_blend_ = {};
  ++blend_generation_;
  if (!f.midpoint_mask) return;
  for (int k = 0; k < playback::kCellBubbles; ++k) {
    const MidpointTarget& t = targets[k];
    if (t.recorded == 0) continue;
    const playback::BubbleSpec b = playback::bubble_spec(k);
    const std::int32_t source = corners_[b.source_corner].configuration;
    if (!((f.midpoint_mask[source] >> b.direction) & 1)) continue;
    const int x = int(2 * b.point[0]), y = int(2 * b.point[1]), z = int(2 * b.point[2]);
    if (onset_) {
      if (!t.in_blend) continue;
      const OnsetPoint& o = t.onset;
      midpoint_blend_[9 * x + 3 * y + z] = {o.R, o.dR, o.depth, -o.grad[0], -o.grad[1], -o.grad[2]};
    }
    midpoint_code_[9 * x + 3 * y + z] = playback::kMidpointDirections * source + b.direction + 1;
  }
}

namespace {

// The data at the points of a cell's lattice with N points per axis (N = 3: the half-spacing
// lattice, 5: a refined cell's quarter-spacing one): value, gradient (row-major, 3 r + a) and
// the cross derivatives [r][pair] (kPair).
template <int N>
struct Lattice {
  double value[N][N][N][3];
  double gradient[N][N][N][9];
  double cross[N][N][N][3][3];
};

// The cross derivatives at every point of L: along each lattice line, the slope of the parabola
// through 3 neighbouring gradients (second order, where differences between 2 points are first
// order). Those in a face's plane use only that face's points: the force stays continuous. Zero
// for the triple derivative, as in the corners' cubic. h: the cell's spacing.
template <int N>
void lattice_cross(const double* h, Lattice<N>* L) {
  auto along = [&](const int(&p)[3], int axis, int component) {
    const int first = std::clamp(p[axis] - 1, 0, N - 3);
    int q[3] = {p[0], p[1], p[2]};
    double g[3];
    for (int i = 0; i < 3; ++i) {
      q[axis] = first + i;
      g[i] = L->gradient[q[0]][q[1]][q[2]][component];
    }
    return lattice_derivative(g[0], g[1], g[2], p[axis] - first, 2.0 * h[axis] / (N - 1));
  };
  for (int x = 0; x < N; ++x)
    for (int y = 0; y < N; ++y)
      for (int z = 0; z < N; ++z) {
        const int p[3] = {x, y, z};
        for (int r = 0; r < 3; ++r)
          for (int q = 0; q < 3; ++q) {
            const int a = kPair[q][0], b = kPair[q][1];
            L->cross[x][y][z][r][q] = 0.5 * (along(p, b, 3 * r + a) + along(p, a, 3 * r + b));
          }
      }
}

// The Hermite coefficients of the (N - 1)^3 sub-cells of L, sub-cell (x, y, z) at
// (x (N - 1) + y) (N - 1) + z, each from the data at its 8 lattice points.
template <int N, class Coefficients>
void sub_cell_coefficients(const Lattice<N>& L, Coefficients* out) {
  for (int sub = 0; sub < (N - 1) * (N - 1) * (N - 1); ++sub) {
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
          [&](int x, int y, int z) -> double& { return out[sub][x][y][r][z]; });
  }
}

// Whether quarter-lattice point (i, j, k) of a refined cell lies on a face or an edge set in
// `constraints` (playback/format.h bits).
bool constrained(const int (&p)[3], std::int32_t constraints) {
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      if (p[a] != 4 * side) continue;
      if (constraints >> playback::refined_face_bit(a, side) & 1) return true;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      // the edges along b and along c on this face
      for (int s2 = 0; s2 < 2; ++s2) {
        // along b: sides of c (next of b) and a (next of c)
        if (p[c] == 4 * s2 && (constraints >> playback::refined_edge_bit(b, s2, side) & 1))
          return true;
        // along c: sides of a (next of c) and b
        if (p[b] == 4 * s2 && (constraints >> playback::refined_edge_bit(c, side, s2) & 1))
          return true;
      }
    }
  return false;
}

}  // namespace

// Hermite with the midpoint stiffness: the cell's 27 lattice points (corners, edge midpoints,
// face and cell centres) get a value, a gradient and cross derivatives each, and each of the 8
// half-spacing cells is a cubic Hermite cell of its own (hermite_coefficients). A corner's are its
// force and stiffness; a midpoint's the recorded ones (in a cell near the contact onset, those the
// blend turns into them: onset_target), else the cell's Hermite interpolant's there. A recorded
// value differs from that interpolant by at most the bubble limit per component and a recorded
// stiffness entry by at most the stiffness limit (Meta): the change bound stays valid. A point
// on a face or an edge depends only on the data of that face or edge, so the force stays
// continuous across faces. A refined cell goes one level further (fit_refined_cell).
void HapticCursor::fit_cell_lattice(const MidpointTarget* targets) {
  const playback::Meta& m = *file_.impl().meta;
  Lattice<3> L;
  hermite_lattice(coef_, m.spacing, L.value, L.gradient);  // the fallback at the midpoints
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    std::copy_n(force_of(c), 3, L.value[2 * o[0]][2 * o[1]][2 * o[2]]);
    std::copy_n(stiffness_of(c), 9, L.gradient[2 * o[0]][2 * o[1]][2 * o[2]]);
  }
  for (int k = 0; k < playback::kCellBubbles; ++k) {
    const playback::BubbleSpec b = playback::bubble_spec(k);
    const int x = int(2 * b.point[0]), y = int(2 * b.point[1]), z = int(2 * b.point[2]);
    double* v = L.value[x][y][z];
    double* g = L.gradient[x][y][z];
    const MidpointTarget& t = targets[k];
    if (!t.fitted) continue;
    const double bound = m.bubble_limit[static_cast<int>(b.kind)];
    for (int r = 0; r < 3; ++r) v[r] += std::clamp(t.force[r] - v[r], -bound, bound);
    if (t.recorded == 2)
      for (int e = 0; e < 9; ++e)
        g[e] = std::clamp(t.stiffness[e], -m.stiffness_limit, m.stiffness_limit);
  }
  lattice_cross(m.spacing, &L);
  sub_cell_coefficients(L, half_coef_.data());
  const std::int32_t slot = refined_cell();
  if (slot >= 0) fit_refined_cell(slot);
}

// The refined cell (docs/playback.md, "Refined cells") the current cell is, or -1: its lowest
// corner is a stored configuration the file has refined points for, whose moves lead to the
// cell's other 7 corners (the points belong to the corners the cell shows).
std::int32_t HapticCursor::refined_cell() const {
  const PlaybackFile::Impl& f = file_.impl();
  const std::int32_t c0 = corners_[0].configuration;
  if (!f.refined_cells || c0 < 0) return -1;
  const std::int32_t slot = f.refined_cells[2 * std::int64_t(c0)];
  if (slot < 0 || slot >= f.num_refined_cells) return -1;
  for (int c = 1; c < 8; ++c) {
    const auto o = corner_offset(c);
    if (corners_[c].configuration < 0 ||
        f.transition(c0, direction_index(o[0], o[1], o[2])) != corners_[c].configuration)
      return -1;
  }
  return slot;
}

// What a refined cell's fit aims at quarter-lattice point p, whose solved force and stiffness
// are `data` (12 values): those, or in a cell near the contact onset those the blend turns into
// them (onset_target), as for the midpoints. False where the blend allows no fit there
// (onset_blend_at): the point then keeps the half cells' interpolant.
bool HapticCursor::refined_target(const int (&p)[3], const double* data, double* out) const {
  if (!onset_) {
    std::copy_n(data, 12, out);
    return true;
  }
  const std::array<double, 3> t = {0.25 * p[0], 0.25 * p[1], 0.25 * p[2]};
  OnsetPoint o;
  return onset_blend_at(t, &o) && onset_target(t, o, data, data + 3, out, out + 3);
}

// A refined cell: its 125 quarter-spacing lattice points get a value, a gradient and cross
// derivatives each, and each of the 64 quarter-spacing cells is a cubic Hermite cell of its own
// — the half cells' construction one level down. The points of the half-spacing lattice keep
// their data; the others take the refined points' force and stiffness
// (a value differs from the half cells' interpolant by at most the largest bubble limit per
// component, a stiffness entry by at most the stiffness limit), or where none was solved the half
// cells' interpolant's. On a face or an edge shared with a cell that is not refined (the
// constraint bits) every point takes the half cells' interpolant's value, gradient and cross
// derivatives: the quarter cells there reproduce it exactly (it is a cubic on each of them), so
// the force stays continuous across the face.
void HapticCursor::fit_refined_cell(std::int32_t slot) {
  const PlaybackFile::Impl& f = file_.impl();
  const playback::Meta& m = *f.meta;
  const std::int32_t constraints = f.refined_cells[2 * std::int64_t(corners_[0].configuration) + 1];
  const double* stored = f.refined_points + 12 * playback::kRefinedPoints * std::int64_t(slot);
  const double limit = std::max({m.bubble_limit[0], m.bubble_limit[1], m.bubble_limit[2]});
  const double half[3] = {0.5 * m.spacing[0], 0.5 * m.spacing[1], 0.5 * m.spacing[2]};
  // The half cells' interpolant at their own lattices, which together are the quarter lattice:
  // point (i, j, k) is in half cell (i, j, k) >= 2 at index (i, j, k) - 2 (that >= 2).
  double hv[8][3][3][3][3], hg[8][3][3][3][9], hc[8][3][3][3][3][3];
  for (int sub = 0; sub < 8; ++sub)
    hermite_lattice(half_coef_[sub], half, hv[sub], hg[sub], &hc[sub]);
  auto in_half = [](int p) { return p >= 2 ? p - 2 : p; };
  Lattice<5> Q;
  bool exact[5][5][5];  // the half cells' interpolant's data, cross derivatives included
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int p[3] = {i, j, k};
        const int sub = (i >= 2 ? 4 : 0) | (j >= 2 ? 2 : 0) | (k >= 2 ? 1 : 0);
        const int x = in_half(i), y = in_half(j), z = in_half(k);
        double* v = Q.value[i][j][k];
        double* g = Q.gradient[i][j][k];
        std::copy_n(hv[sub][x][y][z], 3, v);  // at a half-lattice point: that point's data
        std::copy_n(hg[sub][x][y][z], 9, g);
        const double* data = stored + 12 * (25 * i + 5 * j + k);
        const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
        exact[i][j][k] = constrained(p, constraints) || (!lattice && !finite(data, 12));
        if (lattice || exact[i][j][k]) continue;
        double target[12];
        if (!refined_target(p, data, target)) {
          exact[i][j][k] = true;
          continue;
        }
        for (int r = 0; r < 3; ++r) v[r] += std::clamp(target[r] - v[r], -limit, limit);
        for (int e = 0; e < 9; ++e)
          g[e] = std::clamp(target[3 + e], -m.stiffness_limit, m.stiffness_limit);
      }
  lattice_cross(m.spacing, &Q);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        if (!exact[i][j][k]) continue;
        const int sub = (i >= 2 ? 4 : 0) | (j >= 2 ? 2 : 0) | (k >= 2 ? 1 : 0);
        const auto& c = hc[sub][in_half(i)][in_half(j)][in_half(k)];
        for (int r = 0; r < 3; ++r) std::copy_n(c[r], 3, Q.cross[i][j][k][r]);
      }
  sub_cell_coefficients(Q, quarter_coef_.data());
  refined_ = true;
}

// The trilinear scheme's force (corners and bubbles) and stiffness (the corners' blended) at cell
// position s, as force() returns them before the onset blend.
void HapticCursor::trilinear_at(const std::array<double, 3>& s, double* value,
                                double* stiffness) const {
  std::fill_n(value, 3, 0.0);
  std::fill_n(stiffness, 9, 0.0);
  for (int c = 0; c < 8; ++c) {
    const double w = trilinear_weight(c, s);
    if (w == 0.0) continue;
    for (int r = 0; r < 3; ++r) value[r] += w * force_of(c)[r];
    for (int r = 0; r < 9; ++r) stiffness[r] += w * stiffness_of(c)[r];
  }
  double m[3], dm[3], v[3][2], dv[3][2];
  trilinear_bubble_bases(s, file_.impl().meta->spacing, m, dm, v, dv);
  std::array<double, 3> bubbles{};
  add_bubbles(m, dm, v, dv, &bubbles, nullptr);
  for (int r = 0; r < 3; ++r) value[r] += bubbles[r];
}

// A refined cell with kTrilinear: each point of the quarter-spacing lattice takes the solved
// force and stiffness (through the onset blend near the onset: refined_target; a value clamped
// to within the largest bubble limit of the half-spacing interpolant, a stiffness entry to
// `stiffness_limit`), or where there is none, where the blend allows no fit, at the points of
// the half-spacing lattice and on a face or an edge shared with a cell that is not refined,
// the half-spacing trilinear interpolant's value and blended stiffness. That interpolant is
// trilinear on each half cell, so the quarter cells reproduce it exactly on such a face: the
// force stays continuous across it.
void HapticCursor::fit_refined_trilinear(std::int32_t slot) {
  const PlaybackFile::Impl& f = file_.impl();
  const playback::Meta& m = *f.meta;
  const std::int32_t constraints = f.refined_cells[2 * std::int64_t(corners_[0].configuration) + 1];
  const double* stored = f.refined_points + 12 * playback::kRefinedPoints * std::int64_t(slot);
  const double limit = std::max({m.bubble_limit[0], m.bubble_limit[1], m.bubble_limit[2]});
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int p[3] = {i, j, k};
        std::array<double, 12>& out = quarter_trilinear_[25 * i + 5 * j + k];
        trilinear_at({0.25 * i, 0.25 * j, 0.25 * k}, out.data(), out.data() + 3);
        const double* data = stored + 12 * (25 * i + 5 * j + k);
        const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
        double target[12];
        if (lattice || constrained(p, constraints) || !finite(data, 12) ||
            !refined_target(p, data, target))
          continue;
        for (int r = 0; r < 3; ++r) out[r] += std::clamp(target[r] - out[r], -limit, limit);
        for (int e = 0; e < 9; ++e)
          out[3 + e] = std::clamp(target[3 + e], -m.stiffness_limit, m.stiffness_limit);
      }
  refined_ = true;
}

// The bubbles toward the recorded forces (trilinear, or Hermite in a file without the midpoint
// stiffness): fitted edges first, then faces, then the cell.
void HapticCursor::fit_cell_bubbles(const MidpointTarget* targets) {
  const PlaybackFile::Impl& f = file_.impl();
  if (!f.midpoint_force) return;
  // Hermite: the cell's interpolant at the lattice points, once (the bubbles' points are on it).
  double lattice[3][3][3][3], unused[3][3][3][9];
  if (scheme_ == Scheme::kHermite) hermite_lattice(coef_, f.meta->spacing, lattice, unused);
  auto interpolant = [&](const std::array<double, 3>& t, double* out) {
    if (scheme_ == Scheme::kTrilinear) {
      for (int r = 0; r < 3; ++r) out[r] = 0.0;
      for (int c = 0; c < 8; ++c) {
        const double w = trilinear_weight(c, t);
        if (w == 0.0) continue;
        for (int r = 0; r < 3; ++r) out[r] += w * force_of(c)[r];
      }
      return;
    }
    std::copy_n(lattice[int(2 * t[0])][int(2 * t[1])][int(2 * t[2])], 3, out);
  };
  auto recorded = [&](int k, double* out) {
    if (!targets[k].force_ok) return false;
    std::copy_n(targets[k].force, 3, out);
    return true;
  };
  playback::fit_bubbles(interpolant, recorded, f.meta->bubble_limit, &bubble_);
  num_bubbles_ = 0;
  for (int k = 0; k < playback::kCellBubbles; ++k)
    if (bubble_[k][0] != 0 || bubble_[k][1] != 0 || bubble_[k][2] != 0) ++num_bubbles_;
  // Grouped by shape for force(): edges along a as [r][o1][o2], faces normal to a as [r][o].
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < 3; ++r) {
      for (int o = 0; o < 4; ++o) bubble_edge_[a][r][o >> 1][o & 1] = bubble_[4 * a + o][r];
      for (int o = 0; o < 2; ++o)
        bubble_face_[a][r][o] = bubble_[playback::kEdgeBubbles + 2 * a + o][r];
    }
  for (int r = 0; r < 3; ++r) bubble_cell_[r] = bubble_[playback::kCellBubbles - 1][r];
}

// Adds the cell's bubbles to the interpolated force and, if `slope` is given, their gradient to
// its derivative. Per axis a: m[a] a bubble's factor along the axes it lies on (16 t^2 (1 - t)^2
// for Hermite, the hat 1 - |2 t - 1| for trilinear), v[a][o] its factor across them on side o
// (the scheme's value basis), dm and dv their derivatives per mesh unit. Per component: the
// edges along a as m_a (v_b^T E v_c), the faces normal to a as (F . v_a) m_b m_c, the cell
// m_x m_y m_z.
void HapticCursor::add_bubbles(const double (&m)[3], const double (&dm)[3], const double (&v)[3][2],
                               const double (&dv)[3][2], std::array<double, 3>* value,
                               std::array<double, 9>* slope) const {
  for (int r = 0; r < 3; ++r) {
    double f = bubble_cell_[r] * m[0] * m[1] * m[2];
    double g[3] = {bubble_cell_[r] * dm[0] * m[1] * m[2], bubble_cell_[r] * m[0] * dm[1] * m[2],
                   bubble_cell_[r] * m[0] * m[1] * dm[2]};
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const auto& E = bubble_edge_[a][r];
      // v_b^T E v_c and its derivatives along b and c.
      const double ec0 = E[0][0] * v[c][0] + E[0][1] * v[c][1];
      const double ec1 = E[1][0] * v[c][0] + E[1][1] * v[c][1];
      const double dec0 = E[0][0] * dv[c][0] + E[0][1] * dv[c][1];
      const double dec1 = E[1][0] * dv[c][0] + E[1][1] * dv[c][1];
      const double edge = v[b][0] * ec0 + v[b][1] * ec1;
      f += m[a] * edge;
      g[a] += dm[a] * edge;
      g[b] += m[a] * (dv[b][0] * ec0 + dv[b][1] * ec1);
      g[c] += m[a] * (v[b][0] * dec0 + v[b][1] * dec1);
      const auto& F = bubble_face_[a][r];
      const double face = F[0] * v[a][0] + F[1] * v[a][1];
      const double mbc = m[b] * m[c];
      f += face * mbc;
      g[a] += (F[0] * dv[a][0] + F[1] * dv[a][1]) * mbc;
      g[b] += face * dm[b] * m[c];
      g[c] += face * m[b] * dm[c];
    }
    (*value)[r] += f;
    if (slope)
      for (int a = 0; a < 3; ++a) (*slope)[3 * r + a] += g[a];
  }
}

void HapticCursor::enter_cell(const std::array<std::int32_t, 3>& base) {
  const std::array<Corner, 8> old = corners_;
  const std::array<std::int32_t, 3> old_base = base_;
  base_ = base;
  bool shared[8];
  for (int c = 0; c < 8; ++c) {
    const auto oc = corner_offset(c);
    int k = 0;
    shared[c] = true;
    for (int a = 0; a < 3; ++a) {
      const int d = base[a] + oc[a] - old_base[a];
      shared[c] = shared[c] && (d == 0 || d == 1);
      k |= (d & 1) << (2 - a);
    }
    if (shared[c]) corners_[c] = old[k];
  }
  for (int c = 0; c < 8; ++c)
    if (!shared[c]) resolve_corner(c, old, old_base);
  update_coefficients();
  ++cells_walked_;
}

// Moves the cell from the one holding last_q_ to the one holding q (both clamped to the
// grid), one face at a time in the order the straight segment crosses them.
void HapticCursor::walk_to(const std::array<double, 3>& q) {
  const playback::Meta& m = *file_.impl().meta;
  std::array<std::int32_t, 3> target{};
  for (int a = 0; a < 3; ++a)
    target[a] =
        std::clamp(static_cast<std::int32_t>(std::floor(q[a])), m.lo[a], file_.impl().last_cell(a));
  const std::array<double, 3> q0 = last_q_;
  while (base_ != target) {
    int axis = -1;
    double best = 2.0;
    for (int a = 0; a < 3; ++a) {
      if (base_[a] == target[a]) continue;
      const int step = target[a] > base_[a] ? 1 : -1;
      const double boundary = step > 0 ? base_[a] + 1 : base_[a];
      const double dq = q[a] - q0[a];
      const double t = dq != 0.0 ? (boundary - q0[a]) / dq : 0.0;
      if (axis < 0 || t < best) axis = a, best = t;
    }
    std::array<std::int32_t, 3> next = base_;
    next[axis] += target[axis] > base_[axis] ? 1 : -1;
    enter_cell(next);
  }
}

Force HapticCursor::force(const std::array<double, 3>& probe) {
  const PlaybackFile::Impl& f = file_.impl();
  const playback::Meta& m = *f.meta;
  std::array<double, 3> q{}, p_clamped{};
  Force out;
  for (int a = 0; a < 3; ++a) {
    double g = (probe[a] - m.origin[a]) / m.spacing[a];
    if (!std::isfinite(g)) g = last_q_[a];  // a NaN probe keeps the last position
    const double lo = m.lo[a], hi = m.lo[a] + m.dims[a] - 1;
    // A rounding error off a face (a path interpolated along a flat axis) is still inside.
    if (g < lo - 1e-9 || g > hi + 1e-9) out.inside_grid = false;
    q[a] = std::clamp(g, lo, hi);
    p_clamped[a] = m.origin[a] + q[a] * m.spacing[a];
  }
  walk_to(q);
  last_q_ = q;

  std::array<double, 3> s{};
  for (int a = 0; a < 3; ++a) s[a] = std::clamp(q[a] - base_[a], 0.0, 1.0);
  // The Hermite bases per axis and their derivatives (hermite_bases); lin[a][o] the linear
  // weights.
  double B[3][4], dB[3][4], lin[3][2];
  hermite_bases(s, m.spacing, B, dB);
  for (int a = 0; a < 3; ++a) {
    lin[a][0] = 1.0 - s[a];
    lin[a][1] = s[a];
  }
  std::array<double, 3> value{};
  std::array<double, 9> slope{};    // d(value)/d(probe)
  std::array<double, 9> k_blend{};  // trilinear blend of the corners' stiffness
  // Trilinear (and outside the grid, either scheme): the corners' stiffness blended, and with
  // kTrilinear their forces.
  const bool blended = scheme_ == Scheme::kTrilinear || !out.inside_grid;
  // A fitted refined trilinear cell replaces both below with its quarter lattice's.
  const bool quarter_trilinear = fitted_ && refined_ && scheme_ == Scheme::kTrilinear;
  if (blended && !quarter_trilinear) {
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      const double w = lin[0][o[0]] * lin[1][o[1]] * lin[2][o[2]];
      const double* k = stiffness_of(c);
      for (int r = 0; r < 9; ++r) k_blend[r] += w * k[r];
      if (scheme_ != Scheme::kTrilinear) continue;
      const double* f = force_of(c);
      for (int r = 0; r < 3; ++r) value[r] += w * f[r];
    }
  }
  if (!fitted_) fit_cell();
  if (refined_ && scheme_ == Scheme::kTrilinear) {
    // The quarter-spacing cell holding the probe: its 8 lattice points' force and stiffness
    // interpolated trilinearly (docs/playback.md, "Refined cells").
    value = {};
    k_blend = {};
    int q[3];
    double w[3][2];
    for (int a = 0; a < 3; ++a) {
      q[a] = std::min(static_cast<int>(4.0 * s[a]), 3);
      const double t = std::min(4.0 * s[a] - q[a], 1.0);
      w[a][0] = 1.0 - t, w[a][1] = t;
    }
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      const double wc = w[0][o[0]] * w[1][o[1]] * w[2][o[2]];
      const auto& d = quarter_trilinear_[25 * (q[0] + o[0]) + 5 * (q[1] + o[1]) + q[2] + o[2]];
      for (int r = 0; r < 3; ++r) value[r] += wc * d[r];
      for (int r = 0; r < 9; ++r) k_blend[r] += wc * d[3 + r];
    }
  } else if (refined_) {
    // The quarter-spacing cell holding the probe (docs/playback.md, "Refined cells").
    int sub = 0;
    std::array<double, 3> t{};
    double quarter[3], Bq[3][4], dBq[3][4];
    for (int a = 0; a < 3; ++a) {
      const int q = std::min(static_cast<int>(4.0 * s[a]), 3);
      sub = 4 * sub + q;
      t[a] = std::min(4.0 * s[a] - q, 1.0);
      quarter[a] = 0.25 * m.spacing[a];
    }
    hermite_bases(t, quarter, Bq, dBq);
    hermite_contract(quarter_coef_[sub], Bq, dBq, &value, &slope);
  } else if (lattice_) {
    // The half-spacing cell holding the probe (docs/playback.md, "Between the check-points").
    int sub = 0;
    std::array<double, 3> t{};
    double half[3], Bh[3][4], dBh[3][4];
    for (int a = 0; a < 3; ++a) {
      const int side = s[a] >= 0.5 ? 1 : 0;
      sub |= side << (2 - a);
      t[a] = std::min(2.0 * s[a] - side, 1.0);
      half[a] = 0.5 * m.spacing[a];
    }
    hermite_bases(t, half, Bh, dBh);
    hermite_contract(half_coef_[sub], Bh, dBh, &value, &slope);
  } else if (scheme_ == Scheme::kHermite) {
    hermite_contract(coef_, B, dB, &value, &slope);
  }
  if (num_bubbles_ > 0 && !refined_) {
    // Along its axes a bubble is 16 t^2 (1 - t)^2 (Hermite) or the hat 1 - |2 t - 1|
    // (trilinear); across them the scheme's value basis of its side.
    double mb[3], dmb[3], v[3][2], dv[3][2];
    if (scheme_ == Scheme::kTrilinear) {
      trilinear_bubble_bases(s, m.spacing, mb, dmb, v, dv);
    } else {
      for (int a = 0; a < 3; ++a) {
        const double t = s[a], u = 1.0 - t;
        mb[a] = 16.0 * t * t * u * u;
        dmb[a] = 32.0 * t * u * (u - t) / m.spacing[a];
        v[a][0] = B[a][0], v[a][1] = B[a][2];
        dv[a][0] = dB[a][0], dv[a][1] = dB[a][2];
      }
    }
    add_bubbles(mb, dmb, v, dv, &value,
                scheme_ == Scheme::kHermite && out.inside_grid ? &slope : nullptr);
  }
  if (blended) slope = k_blend;
  const OnsetBlend onset = onset_ ? apply_onset(B, dB, s, &value, &slope) : OnsetBlend{};
  if (!out.inside_grid) {
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) value[r] += slope[3 * r + a] * (probe[a] - p_clamped[a]);
  }
  for (int r = 0; r < 3; ++r) out.value[r] = std::isfinite(value[r]) ? value[r] : 0.0;
  for (int r = 0; r < 9; ++r) out.stiffness[r] = std::isfinite(slope[r]) ? slope[r] : 0.0;
  ++calls_;
  publish(probe, out, s, onset);
  return out;
}

void HapticCursor::publish(const std::array<double, 3>& probe, const Force& f,
                           const std::array<double, 3>& s, const OnsetBlend& onset) {
  Snapshot& slot = slots_[back_];
  slot.sequence = calls_;
  slot.probe = probe;
  slot.force = f.value;
  slot.cell_position = s;
  slot.scheme = scheme_;
  slot.secant_corners = 0;
  slot.onset_weight = onset.weight;
  slot.onset_depth = onset.depth;
  // The probe clear of the body: the body at rest, no midpoint either.
  if (onset.at_rest)
    slot.midpoint.fill(0);
  else
    slot.midpoint = midpoint_code_;
  if (slot_blend_generation_[back_] != blend_generation_) {  // 1.3 KB: only when it changed
    slot.midpoint_blend = midpoint_blend_;
    slot_blend_generation_[back_] = blend_generation_;
  }
  for (int c = 0; c < 8; ++c) {
    const Corner& k = corners_[c];
    const bool secant = onset_ && k.secant;
    slot.weight[c] = trilinear_weight(c, s);
    slot.corner_configuration[c] = onset.at_rest ? -1 : secant ? k.onset->source : k.displacement;
    slot.corner_shift[c] = k.shift;
    if (!onset_) continue;  // the onset arrays are read only with these flags set
    if (secant) slot.secant_corners |= 1 << c;
    // Every corner has onset data but the far ones of a flat cell, which weigh nothing.
    slot.secant[c] = {};
    if (secant) std::copy_n(k.onset->secant, 4, slot.secant[c].begin());
    slot.per_depth[c] = k.depth_model ? k.onset->displacement_per_depth : 0.0;
    slot.depth_source[c] = k.depth_model ? k.onset->depth_source : -1;
  }
  back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & 3u;
}

void HapticCursor::snapshot(Snapshot* out) const {
  if (middle_.load(std::memory_order_acquire) & kFresh)
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & 3u;
  *out = slots_[front_];
}

std::int32_t HapticCursor::anchor_configuration() const {
  int c = 0;
  for (int a = 0; a < 3; ++a) c |= (last_q_[a] - base_[a] >= 0.5 ? 1 : 0) << (2 - a);
  return corners_[c].configuration;
}

std::array<std::int32_t, 3> HapticCursor::anchor_checkpoint() const {
  std::array<std::int32_t, 3> ijk{};
  for (int a = 0; a < 3; ++a) ijk[a] = base_[a] + (last_q_[a] - base_[a] >= 0.5 ? 1 : 0);
  return ijk;
}

static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

}  // namespace hapstate
