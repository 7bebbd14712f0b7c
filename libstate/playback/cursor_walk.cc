// The cursor's cell walk (docs/playback.md, "The cell walk"): anchoring at a zero
// configuration, following the stored transitions cell by cell, extending a corner where none
// leads, and the cell's Hermite coefficients once its corners change.
#include "playback/cursor_core.h"

#include "playback/cell_math.h"
#include "playback/file_impl.h"

#include <algorithm>
#include <cmath>

namespace hapstate::playback {

void CursorCore::reset() { anchor_at(file_.impl().meta->rest_configuration); }

void CursorCore::reset(const std::array<double, 3>& probe) {
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
CursorCore::Corner CursorCore::stored_corner(std::int32_t t) const {
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
void CursorCore::anchor_at(std::int32_t rest) {
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
  publish(p, zero, s, s, rest_state);
}

// Fills corners_[c] of the cell at base_ from the corners of the previous cell `old` (at
// old_base) that it shares: a stored transition from a shared stored corner (the straight
// neighbour first), else an extension of the nearest shared corner. Shared corners were copied.
void CursorCore::resolve_corner(int c, const std::array<Corner, 8>& old,
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

// The Hermite coefficients of the current cell's force: per component, each corner's force and
// stiffness row.
void CursorCore::update_coefficients() {
  prepare_onset();
  local_models_ = false;  // fitted with the cell (fit_cell)
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

void CursorCore::enter_cell(const std::array<std::int32_t, 3>& base) {
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
void CursorCore::walk_to(const std::array<double, 3>& q) {
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
}  // namespace hapstate::playback
