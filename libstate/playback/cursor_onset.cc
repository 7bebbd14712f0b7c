// The cursor near the contact onset (docs/playback.md, "Contact onset"): the interpolated
// clearance, the blend into the depth model, and the secant corners.
#include "playback/cursor_core.h"

#include "playback/cell_lattice.h"
#include "playback/cell_math.h"
#include "playback/depth_model.h"
#include "playback/file_impl.h"
#include "util/triangle_point.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapstate::playback {

// Contact: whether the cell blends in the depth model near the onset (every corner has one,
// so no corner is extended or touching while clear of the rest body, and some corner is within
// the band plus a cell diagonal of the onset: the clearance changes by at most the distance);
// the clearance's Hermite coefficients.
void CursorCore::prepare_onset() {
  const PlaybackFile::Impl& f = file_.impl();
  onset_ = false;
  surface_first_ = surface_end_ = 0;
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
    std::copy_n(corners_[c & ~flat].onset->per_depth_squared, 3, per_depth_squared_[c].begin());
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
  const OnsetCellTest test = onset_cell_test(shallowest, deepest, h);
  if (!test.blend) return;
  onset_ = true;
  clear_cell_ = test.clear;
  // The rest triangles that can be nearest to a point of this cell (sections 24-26; a list
  // out of range, in a damaged file, is not used: clearance() checks each index too).
  if (f.onset_cells) {
    const std::int32_t g = f.point_index(base_);
    const std::int32_t first = f.onset_cells[g], end = f.onset_cells[g + 1];
    if (first >= 0 && first <= end && end <= f.onset_list_size) {
      surface_first_ = first;
      surface_end_ = end;
    }
  }
  scalar_coefficients(
      h, [&](int c) { return gap[c][0]; }, [&](int c, int a) { return gap[c][1 + a]; },
      [&](int x, int y, int z) -> double& { return clearance_coef_[x][y][z]; });
}

// The sphere's clearance from the rest body and its gradient `grad` per mesh unit at cell
// position s, whose bases per axis are B (derivatives dB; both as in force()): in a cell with
// rest triangles (sections 24-26) the distance from the nearest of them minus the radius, exact,
// where the interpolated clearance puts the centre outside the rest body; else interpolated.
double CursorCore::clearance(const std::array<double, 3>& s, const double (&B)[3][4],
                             const double (&dB)[3][4], double (&grad)[3]) const {
  const double g = interpolated_clearance(B, dB, grad);
  const PlaybackFile::Impl& f = file_.impl();
  const double radius = f.meta->contact_radius;
  if (surface_first_ == surface_end_ || g < -radius) return g;
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) p[a] = f.meta->origin[a] + (base_[a] + s[a]) * f.meta->spacing[a];
  TrianglePoint nearest;
  nearest.distance = std::numeric_limits<double>::infinity();
  for (std::int32_t k = surface_first_; k < surface_end_; ++k) {
    const std::int32_t t = f.onset_triangle_list[k];
    if (t < 0 || t >= f.num_onset_triangles) continue;
    const double* x = f.onset_triangles + 9 * std::int64_t(t);
    const TrianglePoint tp =
        closest_point(Eigen::Vector3d(x[0], x[1], x[2]), Eigen::Vector3d(x[3], x[4], x[5]),
                      Eigen::Vector3d(x[6], x[7], x[8]), p);
    if (tp.distance < nearest.distance) nearest = tp;
  }
  if (!(nearest.distance > 0.0)) return g;  // the centre on the surface: no direction
  for (int a = 0; a < 3; ++a) grad[a] = (p[a] - nearest.closest[a]) / nearest.distance;
  return nearest.distance - radius;
}

// The clearance interpolated (Hermite) from the grid points', and its gradient.
double CursorCore::interpolated_clearance(const double (&B)[3][4], const double (&dB)[3][4],
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
// R F + (1 - R) m for 0 < d < band, F the interpolated force, m the depth model (depth_model_at)
// and R = smoothstep(d / band): continuous at the onset and at the band's edge, exact at
// check-points (m = f there) and for a force proportional to the depth. `value` and `slope` hold F
// and its derivative on entry.
CursorCore::OnsetBlend CursorCore::apply_onset(const double (&B)[3][4], const double (&dB)[3][4],
                                               const std::array<double, 3>& s,
                                               std::array<double, 3>* value,
                                               std::array<double, 9>* slope) const {
  const double* h = file_.impl().meta->spacing;
  OnsetBlend blend;
  double grad[3] = {0, 0, 0};
  const double g = clear_cell_ ? 0.0 : clearance(s, B, dB, grad);
  blend.depth = -g;
  if (clear_cell_ || blend.depth <= 0.0) {
    *value = {};
    *slope = {};
    blend.at_rest = true;
    return blend;
  }
  const double band = onset_band(h);
  if (blend.depth >= band) return blend;
  double model[3], dmodel[3][3];
  depth_model_at(s, blend.depth, grad, model, dmodel);
  const double x = blend.depth / band;
  const double R = x * x * (3.0 - 2.0 * x), dR = 6.0 * x * (1.0 - x) / band;  // dR / d(depth)
  for (int r = 0; r < 3; ++r) {
    for (int a = 0; a < 3; ++a)
      (*slope)[3 * r + a] = R * (*slope)[3 * r + a] + (1.0 - R) * dmodel[r][a] -
                            ((*value)[r] - model[r]) * dR * grad[a];
    (*value)[r] = R * (*value)[r] + (1.0 - R) * model[r];
  }
  blend.weight = 1.0 - R;
  return blend;
}

// The depth model at cell position t where the sphere is `depth` deep into the rest body and
// the clearance's gradient is `grad`: model = d (a + b d), a and b the trilinear interpolations of
// the corners' per_depth and per_depth_squared (in a refined cell near the onset, of the quarter
// lattice's: fit_local_depth_models), and its derivative dmodel[r][a] per mesh unit.
void CursorCore::depth_model_at(const std::array<double, 3>& t, double depth,
                                const double (&grad)[3], double (&model)[3],
                                double (&dmodel)[3][3]) const {
  const double* h = file_.impl().meta->spacing;
  // The cell, or with local models the quarter cell holding t: its lowest lattice point, the
  // position in it and the lattice step per mesh unit.
  const int n = local_models_ ? 4 : 1;
  int lo[3] = {0, 0, 0};
  double u[3], per_unit[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = local_models_ ? std::clamp(static_cast<int>(std::floor(4.0 * t[a])), 0, 3) : 0;
    u[a] = n * t[a] - lo[a];
    per_unit[a] = n / h[a];
  }
  double q[3] = {}, b[3] = {}, dq[3][3] = {}, db[3][3] = {};
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    const double w[3] = {o[0] ? u[0] : 1.0 - u[0], o[1] ? u[1] : 1.0 - u[1],
                         o[2] ? u[2] : 1.0 - u[2]};
    const double dw[3] = {(o[0] ? 1.0 : -1.0) * per_unit[0] * w[1] * w[2],
                          (o[1] ? 1.0 : -1.0) * per_unit[1] * w[0] * w[2],
                          (o[2] ? 1.0 : -1.0) * per_unit[2] * w[0] * w[1]};
    const double* a_c = per_depth_[c].data();
    const double* b_c = per_depth_squared_[c].data();
    if (local_models_) {
      const std::array<double, 6>& m =
          local_model_[25 * (lo[0] + o[0]) + 5 * (lo[1] + o[1]) + (lo[2] + o[2])];
      a_c = m.data();
      b_c = m.data() + 3;
    }
    for (int r = 0; r < 3; ++r) {
      q[r] += w[0] * w[1] * w[2] * a_c[r];
      b[r] += w[0] * w[1] * w[2] * b_c[r];
      for (int a = 0; a < 3; ++a) {
        dq[r][a] += dw[a] * a_c[r];
        db[r][a] += dw[a] * b_c[r];
      }
    }
  }
  for (int r = 0; r < 3; ++r) {
    model[r] = depth * (q[r] + b[r] * depth);
    for (int a = 0; a < 3; ++a)
      dmodel[r][a] = -(q[r] + 2.0 * b[r] * depth) * grad[a] + depth * (dq[r][a] + depth * db[r][a]);
  }
}

// A refined cell near the onset: the depth models at its quarter-spacing lattice points. The
// corners' depth models are interpolated over the whole cell; where the force has a ramp near one
// corner (a surface triangle starting to carry force just before it), that corner's model, exact
// there, is 30 % too stiff at the onset a cell away (measured on the liver tip of docs/contact.md).
// The refined points carry the force where they are: a solved point where the sphere is a tenth
// of the band deep or more takes its own model (depth_model, as hapstate-index gives a
// configuration's, at the interpolated clearance, as the fits use), a corner touching by
// shallow_depth keeps its own; every other point takes the mean of its lattice neighbours' own
// (the 26 around it; on the cell's boundary only those on the same face or edge), else the
// corners' models interpolated there. A point on a face or an edge shared with a cell that is not
// refined (the constraint bits) takes the corners' models interpolated there, as that cell does.
// So the models on a face depend only on that face's data: the blend stays continuous across it.
// The blend stays exact at every point with a model of its own.
void CursorCore::fit_local_depth_models(std::int32_t slot) {
  // A refined point shallower than this (a tenth of the band) takes its neighbours' models: its
  // depth is the interpolated clearance's, off by the interpolation's error, which is a large
  // part of a small depth (a 0.3 cm sphere on liverCoarse: its paths' errors 3x larger).
  constexpr double kOwnModelBands = 0.1;
  const PlaybackFile::Impl& f = file_.impl();
  const double* h = f.meta->spacing;
  const std::int32_t constraints =
      f.refined_cells[playback::kRefinedCellInts * std::int64_t(corners_[0].configuration) + 1];
  const double* stored = f.refined_points + 12 * playback::kRefinedPoints * std::int64_t(slot);
  const double shallow = playback::shallow_depth(h), band = onset_band(h);
  auto corner_models = [&](const int(&p)[3], std::array<double, 6>* m) {
    *m = {};
    const std::array<double, 3> t = {0.25 * p[0], 0.25 * p[1], 0.25 * p[2]};
    for (int c = 0; c < 8; ++c) {
      const double w = trilinear_weight(c, t);
      for (int r = 0; r < 3; ++r) {
        (*m)[r] += w * per_depth_[c][r];
        (*m)[3 + r] += w * per_depth_squared_[c][r];
      }
    }
  };
  enum : std::uint8_t { kFill, kOwn, kFixed };
  std::uint8_t kind[125];
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int p[3] = {i, j, k}, n = 25 * i + 5 * j + k;
        std::array<double, 6>& m = local_model_[n];
        kind[n] = kFill;
        if (constrained(p, 4, constraints)) {
          corner_models(p, &m);
          kind[n] = kFixed;
          continue;
        }
        // Only a corner or a solved point can have a model of its own.
        const bool corner = i % 4 == 0 && j % 4 == 0 && k % 4 == 0;
        const bool solved = !(i % 2 == 0 && j % 2 == 0 && k % 2 == 0);
        const double* data = stored + 12 * n;
        if (!corner && !(solved && finite(data, 12))) continue;
        const std::array<double, 3> t = {0.25 * i, 0.25 * j, 0.25 * k};
        double B[3][4], dB[3][4], gap[4], grad[3];
        hermite_bases(t, h, B, dB);
        gap[0] = interpolated_clearance(B, dB, grad);
        std::copy_n(grad, 3, gap + 1);
        if (corner && -gap[0] >= shallow) {
          corner_models(p, &m);  // at a corner: that corner's own model
          kind[n] = kOwn;
        } else if (solved && -gap[0] >= kOwnModelBands * band) {
          playback::depth_model(data, data + 3, gap, band, m.data(), m.data() + 3);
          kind[n] = finite(m.data(), 6) ? kOwn : kFill;
        }
      }
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int p[3] = {i, j, k}, n = 25 * i + 5 * j + k;
        if (kind[n] != kFill) continue;
        std::array<double, 6> sum{};
        int used = 0;
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            for (int dk = -1; dk <= 1; ++dk) {
              const int q[3] = {i + di, j + dj, k + dk};
              bool ok = true;
              for (int a = 0; a < 3; ++a)
                ok = ok && q[a] >= 0 && q[a] <= 4 && (p[a] % 4 != 0 || q[a] == p[a]);
              const int nq = 25 * q[0] + 5 * q[1] + q[2];
              if (!ok || kind[nq] != kOwn) continue;
              for (int e = 0; e < 6; ++e) sum[e] += local_model_[nq][e];
              ++used;
            }
        if (used > 0) {
          for (int e = 0; e < 6; ++e) local_model_[n][e] = sum[e] / used;
        } else {
          corner_models(p, &local_model_[n]);
        }
      }
  local_models_ = true;
}

// The onset blend at cell position t where a midpoint may be fitted through it: R, dR/d(depth),
// the depth and the clearance's gradient (the depth's, negated), interpolated. False where the cell
// is clear of the body, the depth is not positive or R < 1/4 (the blend barely follows F there, and
// a free midpoint's 0 would bend the secant field): the midpoint is left out there.
bool CursorCore::onset_blend_at(const std::array<double, 3>& t, OnsetPoint* out) const {
  if (clear_cell_) return false;
  const double* h = file_.impl().meta->spacing;
  double B[3][4], dB[3][4];
  hermite_bases(t, h, B, dB);
  // The interpolated clearance, not the rest triangles' (a cell entry fits up to 125 points:
  // with a hundred triangles listed that was 0.1-0.2 ms more a call, measured); the two differ
  // by the interpolation's error (0.3 um on the liver of docs/contact.md), which moves a fitted
  // point's blend weight by that much depth.
  out->depth = -interpolated_clearance(B, dB, out->grad);
  if (!(out->depth > 0.0)) return false;
  const double band = onset_band(h);
  const double x = std::min(out->depth / band, 1.0);
  out->R = x * x * (3.0 - 2.0 * x);
  out->dR = 6.0 * x * (1.0 - x) / band;
  return out->R >= 0.25;
}

// The interpolated force F at cell position t, where the onset blend is o (onset_blend_at
// true), for which the blend (apply_onset) returns `felt`: (felt - (1 - R) m) / R, and, if
// `felt_k` is given, the derivative of F for which the blend's derivative is felt_k (row-major,
// per mesh unit): (felt_k - (1 - R) dm/dp + (F - m) R' grad d^T) / R. False where they
// are not finite.
bool CursorCore::onset_target(const std::array<double, 3>& t, const OnsetPoint& o,
                              const double* felt, const double* felt_k, double* out,
                              double* out_k) const {
  const double R = o.R, dR = o.dR, depth = o.depth;
  const double* grad = o.grad;
  double model[3], dmodel[3][3];
  depth_model_at(t, depth, o.grad, model, dmodel);
  for (int r = 0; r < 3; ++r) out[r] = (felt[r] - (1.0 - R) * model[r]) / R;
  if (felt_k)
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a)
        out_k[3 * r + a] =
            (felt_k[3 * r + a] - (1.0 - R) * dmodel[r][a] + (out[r] - model[r]) * dR * grad[a]) / R;
  return finite(out, 3) && (!felt_k || finite(out_k, 9));
}

}  // namespace hapstate::playback
