// The cursor's fit of a cell to the forces recorded half-way through the corners' moves
// (docs/playback.md, "Between the check-points"): the half-spacing Hermite lattice, or bubbles.
#include "playback/cursor_core.h"

#include "playback/cell_bubbles.h"
#include "playback/cell_lattice.h"
#include "playback/file_impl.h"

#include <algorithm>

namespace hapstate::playback {

static_assert(playback::kCellBubbles == 19, "CursorCore::bubble_ holds one per bubble");

// What the corners' moves recorded at bubble k's point (an edge midpoint, a face or the cell
// centre): 0 nothing, 1 the force (into `force`), 2 the force and the stiffness (into
// `stiffness`, row-major). A value is used when both corners of its move are stored
// configurations and the source's move in that direction leads to the target corner's
// configuration (the recorded value belongs to the corners the cell shows).
int CursorCore::recorded_midpoint(int k, double* force, double* stiffness) const {
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
struct CursorCore::MidpointTarget {
  int recorded = 0;       // recorded_midpoint: 0 none, 1 the force, 2 force and stiffness
  bool fitted = false;    // force (and with recorded == 2 stiffness) below are valid
  bool force_ok = false;  // force below is valid (what the bubbles need)
  double force[3] = {};   // N
  double stiffness[9] = {};
  bool in_blend = false;  // near the onset: onset_blend_at allows a fit at the point
  OnsetPoint onset;       // and the blend there
};

void CursorCore::midpoint_target(int k, MidpointTarget* out) const {
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

void CursorCore::fit_cell() {
  fitted_ = true;
  refined_ = false;
  deep_ = deeper_ = false;
  num_bubbles_ = 0;
  lattice_ = scheme_ == Scheme::kHermite && file_.impl().midpoint_stiffness;
  // A refined cell (played back refined by the half-spacing lattice or the trilinear scheme)
  // near the onset takes its depth models from its refined points, before anything is fitted
  // through the blend (the midpoints too), so that every fit and every query sees one blend.
  const std::int32_t slot = lattice_ || scheme_ == Scheme::kTrilinear ? refined_cell() : -1;
  if (slot >= 0 && onset_ && !clear_cell_) fit_local_depth_models(slot);
  MidpointTarget targets[playback::kCellBubbles];
  for (int k = 0; k < playback::kCellBubbles; ++k) midpoint_target(k, &targets[k]);
  find_midpoint_displacements(targets);
  if (lattice_) {
    fit_cell_lattice(targets, slot);
  } else {
    fit_cell_bubbles(targets);
    if (slot >= 0) fit_refined_trilinear(slot);
  }
}

// The midpoints of this cell whose displacements deform() uses (Snapshot::midpoint): those
// whose force the cursor uses (recorded_midpoint) and whose displacements the file holds; in a
// cell near the contact onset, those where the force's fit may use the blend (onset_blend_at),
// with the blend at the point (Snapshot::midpoint_blend) through which deform() fits them.
void CursorCore::find_midpoint_displacements(const MidpointTarget* targets) {
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

// Hermite with the midpoint stiffness: the cell's 27 lattice points (corners, edge midpoints,
// face and cell centres) get a value, a gradient and cross derivatives each, and each of the 8
// half-spacing cells is a cubic Hermite cell of its own (hermite_coefficients). A corner's are its
// force and stiffness; a midpoint's the recorded ones (in a cell near the contact onset, those the
// blend turns into them: onset_target), else the cell's Hermite interpolant's there. A recorded
// value differs from that interpolant by at most the bubble limit per component and a recorded
// stiffness entry by at most the stiffness limit (Meta): the change bound stays valid. A point
// on a face or an edge depends only on the data of that face or edge, so the force stays
// continuous across faces. A refined cell goes one level further (fit_refined_cell).
void CursorCore::fit_cell_lattice(const MidpointTarget* targets, std::int32_t slot) {
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
  if (slot >= 0) fit_refined_cell(slot);
}

// The trilinear scheme's force (corners and bubbles) and stiffness (the corners' blended) at cell
// position s, as force() returns them before the onset blend.
void CursorCore::trilinear_at(const std::array<double, 3>& s, double* value,
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

// The bubbles toward the recorded forces (trilinear, or Hermite in a file without the midpoint
// stiffness): fitted edges first, then faces, then the cell.
void CursorCore::fit_cell_bubbles(const MidpointTarget* targets) {
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
void CursorCore::add_bubbles(const double (&m)[3], const double (&dm)[3], const double (&v)[3][2],
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
}  // namespace hapstate::playback
