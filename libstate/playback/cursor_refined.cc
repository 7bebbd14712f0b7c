// The cursor in a refined cell (docs/playback.md, "Refined cells"): the quarter-spacing lattice
// of solved points, the eighth-spacing one where the cell has it and the sixteenth-spacing one
// in the eighth cells with solves of their own, Hermite or trilinear.
#include "playback/cursor_core.h"

#include "playback/cell_lattice.h"
#include "playback/file_impl.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace hapstate::playback {

namespace {

// A refined point's solved force and stiffness (`target`, 12 values) taken into the data at a
// lattice point that holds the coarser interpolant's: the value moved toward the force by at most
// the largest bubble limit per component (Meta), each stiffness entry clamped to the stiffness
// limit, so the change bound stays valid (docs/playback.md, "Refined cells").
void take_solved(const playback::Meta& m, const double* target, double* value, double* gradient) {
  const double limit = std::max({m.bubble_limit[0], m.bubble_limit[1], m.bubble_limit[2]});
  for (int r = 0; r < 3; ++r) value[r] += std::clamp(target[r] - value[r], -limit, limit);
  for (int e = 0; e < 9; ++e)
    gradient[e] = std::clamp(target[3 + e], -m.stiffness_limit, m.stiffness_limit);
}

// The slope of a solved point (i, j, k) of an eighth- or sixteenth-spacing lattice (N = 9, 17)
// limited by the values around it (docs/playback.md, "Refined cells"): a solved stiffness is the
// derivative on one side of a kink of the contact force (a triangle starting to carry force),
// which can be several times the force's slope a lattice step away, and a cubic through it
// overshoots by about that difference times the step. Each entry (component r, axis a) of the
// gradient is clamped into the interval spanned by the backward and the forward difference of the
// values along a, widened each way by half its width plus a tenth of the largest difference at
// the point: for a smooth force the derivative lies in it (the differences err by the step
// squared), so the point keeps its solved stiffness there. Along an axis where the point is on
// the lattice's boundary it keeps it too. Reads the values of the point and its 6 neighbours.
template <int N>
void limit_slope(const double* h, Lattice<N>* L, int i, int j, int k) {
  const int p[3] = {i, j, k};
  double back[3][3] = {}, ahead[3][3] = {}, scale = 0;  // [r][a]
  for (int a = 0; a < 3; ++a) {
    if (p[a] == 0 || p[a] == N - 1) continue;
    int lo[3] = {i, j, k}, hi[3] = {i, j, k};
    --lo[a], ++hi[a];
    const double step = h[a] / (N - 1);
    for (int r = 0; r < 3; ++r) {
      const double v = L->value[i][j][k][r];
      back[r][a] = (v - L->value[lo[0]][lo[1]][lo[2]][r]) / step;
      ahead[r][a] = (L->value[hi[0]][hi[1]][hi[2]][r] - v) / step;
      scale = std::max({scale, std::abs(back[r][a]), std::abs(ahead[r][a])});
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (p[a] == 0 || p[a] == N - 1) continue;
    for (int r = 0; r < 3; ++r) {
      const double slack = 0.5 * std::abs(ahead[r][a] - back[r][a]) + 0.1 * scale;
      double& g = L->gradient[i][j][k][3 * r + a];
      g = std::clamp(g, std::min(back[r][a], ahead[r][a]) - slack,
                     std::max(back[r][a], ahead[r][a]) + slack);
    }
  }
}

// The cell of a lattice with `n` steps per axis holding the lattice point p of a lattice with
// twice as many (the lower one on a boundary, as lattice_trilinear_at picks): its index, and
// p's position in it (0, 1/2 or 1 per axis).
int coarse_cell(const int (&p)[3], int n, std::array<double, 3>* t) {
  int sub = 0;
  for (int a = 0; a < 3; ++a) {
    const int q = std::min(p[a] / 2, n - 1);
    sub = n * sub + q;
    (*t)[a] = 0.5 * (p[a] - 2 * q);
  }
  return sub;
}

}  // namespace

// The refined cell (docs/playback.md, "Refined cells") the current cell is, or -1: its lowest
// corner is a stored configuration the file has refined points for, whose moves lead to the
// cell's other 7 corners (the points belong to the corners the cell shows).
std::int32_t CursorCore::refined_cell() const {
  const PlaybackFile::Impl& f = file_.impl();
  const std::int32_t c0 = corners_[0].configuration;
  if (!f.refined_cells || c0 < 0) return -1;
  const std::int32_t slot = f.refined_cells[playback::kRefinedCellInts * std::int64_t(c0)];
  if (slot < 0 || slot >= f.num_refined_cells) return -1;
  for (int c = 1; c < 8; ++c) {
    const auto o = corner_offset(c);
    if (corners_[c].configuration < 0 ||
        f.transition(c0, direction_index(o[0], o[1], o[2])) != corners_[c].configuration)
      return -1;
  }
  return slot;
}

// The lattice below the quarter-spacing one of the current cell, a refined cell, whose slot is
// in column `column` of section 20 (2: eighth-spacing, section 23; 4: sixteenth-spacing, section
// 27, `count` lattices), or -1.
std::int32_t CursorCore::deep_slot(int column, std::int32_t count) const {
  const PlaybackFile::Impl& f = file_.impl();
  const std::int32_t slot =
      f.refined_cells[playback::kRefinedCellInts * std::int64_t(corners_[0].configuration) +
                      column];
  return slot >= 0 && slot < count ? slot : -1;
}

// What a refined cell's fit aims at lattice point p (`step` cell spacings apart: 1/4 or 1/8),
// whose solved force and stiffness are `data` (12 values): those, or in a cell near the contact
// onset those the blend turns into them (onset_target), as for the midpoints. False where the
// blend allows no fit there (onset_blend_at): the point then keeps the coarser interpolant.
bool CursorCore::refined_target(const int (&p)[3], double step, const double* data,
                                double* out) const {
  if (!onset_) {
    std::copy_n(data, 12, out);
    return true;
  }
  const std::array<double, 3> t = {step * p[0], step * p[1], step * p[2]};
  OnsetPoint o;
  return onset_blend_at(t, &o) && onset_target(t, o, data, data + 3, out, out + 3);
}

// Snapshot::sway_position in a refined contact cell (Hermite; docs/playback.md, "Refined cells"):
// the refined points hold force and stiffness but no displacements, so the displacements come
// from the half cells, whose force misses the refined one (`value`, at cell position s) by a few
// per cent where the contact force has a kink. Away from the sphere the body's displacement is
// nearly linear in the felt force (its sway: under a 1.5 mm sphere on the bunny's back the nodes
// farther than 0.3 units are within 1.4 % of a linear map of the force over a path), and the half
// cells' displacements follow their own force, so where the half cells' force is `value` they
// show the sway that goes with it. Two Newton steps on F_half(s + dp) = value, each regularised
// ((K^T K + (0.05 |K|_F)^2) dp = K^T df, K the half cells' stiffness there: a frictionless
// contact is soft along the surface), dp at most a quarter of the smallest spacing, kept in the
// cell (one step: the bunny's worst path 13.9 %, two: 4.0 %). s where the stiffness is zero.
std::array<double, 3> CursorCore::shown_position(const std::array<double, 3>& s,
                                                 const std::array<double, 3>& value) const {
  constexpr int kSteps = 2;
  constexpr double kRegularisation = 0.05;
  const double* h = file_.impl().meta->spacing;
  const double limit = 0.25 * std::min({h[0], h[1], h[2]});
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
  std::array<double, 3> shown = s;
  for (int step = 0; step < kSteps; ++step) {
    std::array<double, 3> half{};
    std::array<double, 9> k{};
    sub_cell_at(shown, 2, &half, &k);
    const Eigen::Matrix3d K =
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(k.data());
    const Eigen::Vector3d df(value[0] - half[0], value[1] - half[1], value[2] - half[2]);
    const double norm = K.norm(), mu = kRegularisation * norm;
    if (!(norm > 0) || !df.allFinite() || !K.allFinite()) break;
    const Eigen::Matrix3d A = K.transpose() * K + mu * mu * Eigen::Matrix3d::Identity();
    dp += A.ldlt().solve(K.transpose() * df);
    const double length = dp.norm();
    if (!std::isfinite(length)) return s;
    if (length > limit) dp *= limit / length;
    for (int a = 0; a < 3; ++a) {
      shown[a] = std::clamp(s[a] + dp[a] / h[a], 0.0, 1.0);
      dp[a] = (shown[a] - s[a]) * h[a];
    }
  }
  return shown;
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
  const std::int32_t constraints =
      f.refined_cells[playback::kRefinedCellInts * std::int64_t(corners_[0].configuration) + 1];
  const double* stored = f.refined_points + 12 * playback::kRefinedPoints * std::int64_t(slot);
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
        for (int r = 0; r < 3; ++r) std::copy_n(hc[sub][x][y][z][r], 3, Q.cross[i][j][k][r]);
        const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
        exact[i][j][k] = constrained(p, 4, constraints) || (!lattice && !finite(data, 12));
        if (lattice || exact[i][j][k]) continue;
        double target[12];
        if (!refined_target(p, 0.25, data, target)) {
          exact[i][j][k] = true;
          continue;
        }
        take_solved(m, target, v, g);
      }
  lattice_cross(m.spacing, &Q, exact);
  sub_cell_coefficients(Q, quarter_coef_.data());
  refined_ = true;
  fit_deep();
}

// A refined cell's eighth-spacing lattice (depth 2): the quarter cells' construction one level
// down. Its 729 points take the quarter cells' interpolant's value, gradient and cross
// derivatives; the points of the quarter-spacing lattice keep their value and gradient, the
// others take the solved force and stiffness (clamped and fitted through the onset blend as in
// fit_refined_cell), their slopes limited by the values around them (limit_slope); the cross
// derivatives are recomputed along the lattice lines but at the points that keep the quarter
// cells' interpolant (on a face or an edge whose neighbour has no eighth-spacing lattice, a point
// without a solve): the eighth cells there reproduce the quarter cells' cubic on the face, so the
// force stays continuous. Its sixteenth-spacing lattice (depth 3) is the same construction from
// the eighth cells, but there every point without a solve of its own keeps the eighth cells'
// interpolant, the eighth-spacing points included: an eighth cell none of whose 27 points was
// solved is its own cubic (sixteenth_here), so depth 3 changes nothing away from its solves.
// Entering the cell fits nothing yet (either scheme): a cell's points, and the points their
// cross derivatives and slopes read, are fitted when the probe enters it (deep_cell_at,
// deep_trilinear_cell_at), so a query pays for a few dozen points, not 729 or 4913.
void CursorCore::fit_deep() {
  const PlaybackFile::Impl& f = file_.impl();
  const std::int64_t row = playback::kRefinedCellInts * std::int64_t(corners_[0].configuration);
  auto reset = [&](auto& D, const double* stored, int column) {
    constexpr int n = std::extent_v<decltype(D.stage)>;
    D.constraints = f.refined_cells[row + column + 1];
    D.stored = stored;
    std::fill_n(&D.stage[0][0][0], n * n * n, std::uint8_t{0});
    std::fill_n(&D.trilinear_ready[0][0][0], n * n * n, false);
    std::fill(D.sub_ready.begin(), D.sub_ready.end(), std::uint8_t{0});
    D.sub = -1;
  };
  const std::int32_t eighth = eighth_ ? deep_slot(2, f.num_eighth_cells) : -1;
  deep_ = eighth >= 0;
  if (!deep_) return;
  reset(*eighth_, f.eighth_points + 12 * playback::kEighthPoints * std::int64_t(eighth), 2);
  const std::int32_t sixteenth = sixteenth_ ? deep_slot(4, f.num_sixteenth_cells) : -1;
  deeper_ = sixteenth >= 0;
  if (deeper_)
    reset(*sixteenth_,
          f.sixteenth_points + 12 * playback::kSixteenthPoints * std::int64_t(sixteenth), 4);
}

// The coefficients of eighth cell `sub` (64 i + 8 j + k) of the current deep cell, its points
// fitted first (a sixteenth-spacing point's base reads them).
const CursorCore::CellCoefficients& CursorCore::eighth_coefficients(int sub) {
  DeepCell<9>& E = *eighth_;
  if (!E.sub_ready[std::size_t(sub)]) {
    const int lo[3] = {sub / 64, sub / 8 % 8, sub % 8};
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      deep_point(E, lo[0] + o[0], lo[1] + o[1], lo[2] + o[2], 3);
    }
    sub_cell_coefficient(E.lattice, sub, &E.sub_coef[std::size_t(sub)]);
    E.sub_ready[std::size_t(sub)] = 1;
  }
  return E.sub_coef[std::size_t(sub)];
}

// Point (i, j, k) of lattice D: the coarser lattice's interpolant there (the quarter cells for
// the eighth-spacing lattice, the eighth cells for the sixteenth-spacing one; any cell holding
// the point gives the same data: value, gradient and cross derivatives are continuous across
// their faces) and, at a solved point, the solve's force and stiffness.
template <int N>
void CursorCore::deep_base(DeepCell<N>& D, int i, int j, int k) {
  static_assert(N == 9 || N == 17);
  const playback::Meta& m = *file_.impl().meta;
  Lattice<N>& L = D.lattice;
  const int p[3] = {i, j, k};
  constexpr int coarse = (N - 1) / 2;  // the coarser lattice's steps per axis
  const double h[3] = {m.spacing[0] / coarse, m.spacing[1] / coarse, m.spacing[2] / coarse};
  std::array<double, 3> t{};
  const int sub = coarse_cell(p, coarse, &t);
  if constexpr (N == 9) {
    hermite_point(quarter_coef_[std::size_t(sub)], h, t, L.value[i][j][k], L.gradient[i][j][k],
                  L.cross[i][j][k]);
  } else {
    hermite_point(eighth_coefficients(sub), h, t, L.value[i][j][k], L.gradient[i][j][k],
                  L.cross[i][j][k]);
  }
  const double* data = D.stored + 12 * ((N * i + j) * N + k);
  const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
  bool& exact = D.exact[i][j][k];
  exact = constrained(p, N - 1, D.constraints) || (!lattice && !finite(data, 12)) ||
          (N == 17 && lattice);
  if (lattice || exact) return;
  double target[12];
  if (!refined_target(p, 1.0 / (N - 1), data, target)) {
    exact = true;
    return;
  }
  take_solved(m, target, L.value[i][j][k], L.gradient[i][j][k]);
}

// Brings point (i, j, k) of lattice D to `stage` (DeepCell::stage): its limited slope reads its
// neighbours' values, its cross derivatives the limited gradients along its lattice lines.
template <int N>
void CursorCore::deep_point(DeepCell<N>& D, int i, int j, int k, int stage) {
  std::uint8_t& at = D.stage[i][j][k];
  if (at >= stage) return;
  const int p[3] = {i, j, k};
  if (at < 1) {
    deep_base(D, i, j, k);
    at = 1;
  }
  const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
  const double* h = file_.impl().meta->spacing;
  if (stage >= 2 && at < 2) {
    if (!lattice && !D.exact[i][j][k]) {
      for (int a = 0; a < 3; ++a)
        for (int d = -1; d <= 1; d += 2) {
          int q[3] = {i, j, k};
          q[a] += d;
          if (q[a] >= 0 && q[a] <= N - 1) deep_point(D, q[0], q[1], q[2], 1);
        }
      limit_slope(h, &D.lattice, i, j, k);
    }
    at = 2;
  }
  if (stage >= 3 && at < 3) {
    if (!D.exact[i][j][k]) {
      for (int a = 0; a < 3; ++a) {
        const int first = std::clamp(p[a] - 1, 0, N - 3);
        for (int n = 0; n < 3; ++n) {
          int q[3] = {i, j, k};
          q[a] = first + n;
          deep_point(D, q[0], q[1], q[2], 2);
        }
      }
      lattice_point_cross(h, &D.lattice, i, j, k);
    }
    at = 3;
  }
}

// The Hermite cell of lattice D holding s in a deep refined cell: its value and derivative (its
// points and coefficients fitted when the probe enters it).
template <int N>
void CursorCore::deep_cell_at(DeepCell<N>& D, const std::array<double, 3>& s,
                              std::array<double, 3>* value, std::array<double, 9>* slope) {
  const double* h = file_.impl().meta->spacing;
  constexpr int n = N - 1;
  int sub = 0, lo[3];
  std::array<double, 3> t{};
  double spacing[3], B[3][4], dB[3][4];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::min(static_cast<int>(n * s[a]), n - 1);
    sub = n * sub + lo[a];
    t[a] = std::min(n * s[a] - lo[a], 1.0);
    spacing[a] = h[a] / n;
  }
  if (sub != D.sub) {
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      deep_point(D, lo[0] + o[0], lo[1] + o[1], lo[2] + o[2], 3);
    }
    sub_cell_coefficient(D.lattice, sub, &D.coef);
    D.sub = sub;
  }
  hermite_bases(t, spacing, B, dB);
  hermite_contract(D.coef, B, dB, value, slope);
}

// Whether the eighth cell holding s in a cell with a sixteenth-spacing lattice has a point of
// that lattice with a solve of its own (not on a constrained face or edge); without one the
// eighth cell's cubic is the sixteenth-spacing interpolant there.
bool CursorCore::sixteenth_here(const std::array<double, 3>& s) {
  DeepCell<17>& D = *sixteenth_;
  int lo[3];
  for (int a = 0; a < 3; ++a) lo[a] = std::min(static_cast<int>(8.0 * s[a]), 7);
  std::uint8_t& known = D.sub_ready[std::size_t(64 * lo[0] + 8 * lo[1] + lo[2])];
  if (known == 0) {
    known = 1;
    for (int i = 2 * lo[0]; i <= 2 * lo[0] + 2; ++i)
      for (int j = 2 * lo[1]; j <= 2 * lo[1] + 2; ++j)
        for (int k = 2 * lo[2]; k <= 2 * lo[2] + 2; ++k) {
          const int p[3] = {i, j, k};
          if ((i % 2 || j % 2 || k % 2) && finite(D.stored + 12 * ((17 * i + j) * 17 + k), 12) &&
              !constrained(p, 16, D.constraints))
            known = 2;
        }
  }
  return known == 2;
}

// A deep refined cell's interpolant at s: its sixteenth-spacing cell where the eighth cell holding
// s has solved sixteenth-spacing points, else its eighth-spacing cell.
void CursorCore::eighth_at(const std::array<double, 3>& s, std::array<double, 3>* value,
                           std::array<double, 9>* slope) {
  if (deeper_ && sixteenth_here(s))
    deep_cell_at(*sixteenth_, s, value, slope);
  else
    deep_cell_at(*eighth_, s, value, slope);
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
  const std::int32_t constraints =
      f.refined_cells[playback::kRefinedCellInts * std::int64_t(corners_[0].configuration) + 1];
  const double* stored = f.refined_points + 12 * playback::kRefinedPoints * std::int64_t(slot);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int p[3] = {i, j, k};
        std::array<double, 12>& out = quarter_trilinear_[25 * i + 5 * j + k];
        trilinear_at({0.25 * i, 0.25 * j, 0.25 * k}, out.data(), out.data() + 3);
        const double* data = stored + 12 * (25 * i + 5 * j + k);
        const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
        double target[12];
        if (lattice || constrained(p, 4, constraints) || !finite(data, 12) ||
            !refined_target(p, 0.25, data, target))
          continue;
        take_solved(m, target, out.data(), out.data() + 3);
      }
  refined_ = true;
  fit_deep();
}

// A deep refined cell with kTrilinear: point (i, j, k) of lattice D takes the solved force and
// stiffness (as in fit_refined_trilinear, against the coarser lattice's trilinear interpolant:
// the quarter-spacing one for the eighth-spacing lattice, the eighth-spacing one for the
// sixteenth), or where there is none, at the points of the coarser lattice and on a face or an
// edge whose neighbour has no such lattice, that interpolant's value and stiffness: trilinear on
// each coarser cell, so the finer cells reproduce it there.
template <int N>
void CursorCore::deep_trilinear_point(DeepCell<N>& D, int i, int j, int k) {
  if (D.trilinear_ready[i][j][k]) return;
  D.trilinear_ready[i][j][k] = true;
  const playback::Meta& m = *file_.impl().meta;
  const int p[3] = {i, j, k};
  constexpr int coarse = (N - 1) / 2;
  std::array<double, 12>& out = D.trilinear[std::size_t((N * i + j) * N + k)];
  std::array<double, 3> value{};
  std::array<double, 9> stiffness{};
  const std::array<double, 3> at = {double(i) / (N - 1), double(j) / (N - 1), double(k) / (N - 1)};
  if constexpr (N == 9) {
    lattice_trilinear_at(at, coarse, quarter_trilinear_.data(), &value, &stiffness);
  } else {
    std::array<double, 3> t{};
    const int sub = coarse_cell(p, coarse, &t);
    const int lo[3] = {sub / 64, sub / 8 % 8, sub % 8};
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      deep_trilinear_point(*eighth_, lo[0] + o[0], lo[1] + o[1], lo[2] + o[2]);
    }
    lattice_trilinear_at(at, coarse, eighth_->trilinear.data(), &value, &stiffness);
  }
  std::copy(value.begin(), value.end(), out.begin());
  std::copy(stiffness.begin(), stiffness.end(), out.begin() + 3);
  const double* data = D.stored + 12 * ((N * i + j) * N + k);
  const bool lattice = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
  double target[12];
  if (lattice || constrained(p, N - 1, D.constraints) || !finite(data, 12) ||
      !refined_target(p, 1.0 / (N - 1), data, target))
    return;
  take_solved(m, target, out.data(), out.data() + 3);
}

// The trilinear cell of lattice D holding s in a deep refined cell (its 8 points fitted first).
template <int N>
void CursorCore::deep_trilinear_cell_at(DeepCell<N>& D, const std::array<double, 3>& s,
                                        std::array<double, 3>* value, std::array<double, 9>* k) {
  int lo[3];
  for (int a = 0; a < 3; ++a) lo[a] = std::min(static_cast<int>((N - 1) * s[a]), N - 2);
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    deep_trilinear_point(D, lo[0] + o[0], lo[1] + o[1], lo[2] + o[2]);
  }
  lattice_trilinear_at(s, N - 1, D.trilinear.data(), value, k);
}

// A deep refined cell with kTrilinear at s: its sixteenth-spacing lattice where the eighth cell
// holding s has solved sixteenth-spacing points (sixteenth_here), else its eighth-spacing one.
void CursorCore::eighth_trilinear_at(const std::array<double, 3>& s, std::array<double, 3>* value,
                                     std::array<double, 9>* k) {
  if (deeper_ && sixteenth_here(s))
    deep_trilinear_cell_at(*sixteenth_, s, value, k);
  else
    deep_trilinear_cell_at(*eighth_, s, value, k);
}
}  // namespace hapstate::playback
