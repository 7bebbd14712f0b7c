// The cursor in a refined cell (docs/playback.md, "Refined cells"): the quarter-spacing lattice
// of solved points, Hermite or trilinear.
#include "playback/cursor_core.h"

#include "playback/cell_lattice.h"
#include "playback/file_impl.h"

#include <algorithm>

namespace hapstate::playback {

namespace {

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

// The refined cell (docs/playback.md, "Refined cells") the current cell is, or -1: its lowest
// corner is a stored configuration the file has refined points for, whose moves lead to the
// cell's other 7 corners (the points belong to the corners the cell shows).
std::int32_t CursorCore::refined_cell() const {
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
bool CursorCore::refined_target(const int (&p)[3], const double* data, double* out) const {
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
void CursorCore::fit_refined_cell(std::int32_t slot) {
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

// A refined cell with kTrilinear: each point of the quarter-spacing lattice takes the solved
// force and stiffness (through the onset blend near the onset: refined_target; a value clamped
// to within the largest bubble limit of the half-spacing interpolant, a stiffness entry to
// `stiffness_limit`), or where there is none, where the blend allows no fit, at the points of
// the half-spacing lattice and on a face or an edge shared with a cell that is not refined,
// the half-spacing trilinear interpolant's value and blended stiffness. That interpolant is
// trilinear on each half cell, so the quarter cells reproduce it exactly on such a face: the
// force stays continuous across it.
void CursorCore::fit_refined_trilinear(std::int32_t slot) {
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
}  // namespace hapstate::playback
