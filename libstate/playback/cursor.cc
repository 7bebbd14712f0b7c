// HapticCursor: the public cursor, and its core's haptic query (docs/playback.md). The core's
// other rooms: cursor_walk.cc (the cell walk), cursor_onset.cc (the contact onset blend),
// cursor_midpoints.cc (the midpoint fit), cursor_refined.cc (refined cells), cursor_snapshot.cc
// (the snapshot buffer). Nothing here allocates, locks or calls the system after construction.
#include "playback/cursor_core.h"

#include "playback/cell_math.h"
#include "playback/file_impl.h"

#include <algorithm>
#include <cmath>

namespace hapstate {

HapticCursor::HapticCursor(const PlaybackFile& file, Scheme scheme)
    : core_(std::make_unique<playback::CursorCore>(file, scheme)) {}
HapticCursor::~HapticCursor() = default;

void HapticCursor::reset() { core_->reset(); }
void HapticCursor::reset(const std::array<double, 3>& probe) { core_->reset(probe); }
Force HapticCursor::force(const std::array<double, 3>& probe) { return core_->force(probe); }
void HapticCursor::set_scheme(Scheme scheme) { core_->set_scheme(scheme); }
Scheme HapticCursor::scheme() const { return core_->scheme(); }
std::int32_t HapticCursor::anchor_configuration() const { return core_->anchor_configuration(); }
std::array<std::int32_t, 3> HapticCursor::anchor_checkpoint() const {
  return core_->anchor_checkpoint();
}
CornerSource HapticCursor::corner_source(int corner) const { return core_->corner_source(corner); }
std::int32_t HapticCursor::corner_configuration(int corner) const {
  return core_->corner_configuration(corner);
}
std::uint64_t HapticCursor::cells_walked() const { return core_->cells_walked(); }
void HapticCursor::snapshot(Snapshot* out) const { core_->snapshot(out); }

namespace playback {

CursorCore::CursorCore(const PlaybackFile& file, Scheme scheme) : file_(file), scheme_(scheme) {
  if (file.impl().eighth_points) eighth_ = std::make_unique<DeepCell<9>>();
  if (file.impl().sixteenth_points) {
    sixteenth_ = std::make_unique<DeepCell<17>>();
    sixteenth_->sub_ready.assign(512, 0);
    eighth_->sub_coef.resize(512);
    eighth_->sub_ready.assign(512, 0);
  }
  reset();
}

// The probe's cell position s (clamped to the cell) after walking to it; whether the probe is
// inside the grid, and the nearest point of the grid `clamped`.
std::array<double, 3> CursorCore::locate(const std::array<double, 3>& probe, bool* inside,
                                         std::array<double, 3>* clamped) {
  const playback::Meta& m = *file_.impl().meta;
  std::array<double, 3> q{};
  for (int a = 0; a < 3; ++a) {
    double g = (probe[a] - m.origin[a]) / m.spacing[a];
    if (!std::isfinite(g)) g = last_q_[a];  // a NaN probe keeps the last position
    const double lo = m.lo[a], hi = m.lo[a] + m.dims[a] - 1;
    // A rounding error off a face (a path interpolated along a flat axis) is still inside.
    if (g < lo - 1e-9 || g > hi + 1e-9) *inside = false;
    q[a] = std::clamp(g, lo, hi);
    (*clamped)[a] = m.origin[a] + q[a] * m.spacing[a];
  }
  walk_to(q);
  last_q_ = q;
  std::array<double, 3> s{};
  for (int a = 0; a < 3; ++a) s[a] = std::clamp(q[a] - base_[a], 0.0, 1.0);
  return s;
}

// The corners' stiffness blended trilinearly at s into `k`, and with kTrilinear their forces
// into `value`.
void CursorCore::corner_blend(const std::array<double, 3>& s, std::array<double, 3>* value,
                              std::array<double, 9>* k) const {
  for (int c = 0; c < 8; ++c) {
    const double w = trilinear_weight(c, s);
    const double* kc = stiffness_of(c);
    for (int r = 0; r < 9; ++r) (*k)[r] += w * kc[r];
    if (scheme_ != Scheme::kTrilinear) continue;
    const double* fc = force_of(c);
    for (int r = 0; r < 3; ++r) (*value)[r] += w * fc[r];
  }
}

// A refined cell with kTrilinear: the cell of its lattice with n steps per axis (4: quarter
// spacings, 8: eighth ones; `lattice` (n + 1)^3 points, x-major) holding s, its 8 points' force
// and stiffness interpolated trilinearly (docs/playback.md, "Refined cells").
void CursorCore::lattice_trilinear_at(const std::array<double, 3>& s, int n,
                                      const std::array<double, 12>* lattice,
                                      std::array<double, 3>* value,
                                      std::array<double, 9>* k) const {
  *value = {};
  *k = {};
  int q[3];
  double w[3][2];
  for (int a = 0; a < 3; ++a) {
    q[a] = std::min(static_cast<int>(n * s[a]), n - 1);
    const double t = std::min(n * s[a] - q[a], 1.0);
    w[a][0] = 1.0 - t, w[a][1] = t;
  }
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_offset(c);
    const double wc = w[0][o[0]] * w[1][o[1]] * w[2][o[2]];
    const auto& d = lattice[((q[0] + o[0]) * (n + 1) + q[1] + o[1]) * (n + 1) + q[2] + o[2]];
    for (int r = 0; r < 3; ++r) (*value)[r] += wc * d[r];
    for (int r = 0; r < 9; ++r) (*k)[r] += wc * d[3 + r];
  }
}

// The Hermite sub-cell holding s of a cell split `n` ways per axis (2: the half-spacing cells,
// 4: a refined cell's quarter-spacing ones; docs/playback.md): its value and derivative.
void CursorCore::sub_cell_at(const std::array<double, 3>& s, int n, std::array<double, 3>* value,
                             std::array<double, 9>* slope) const {
  const double* h = file_.impl().meta->spacing;
  int sub = 0;
  std::array<double, 3> t{};
  double spacing[3], B[3][4], dB[3][4];
  for (int a = 0; a < 3; ++a) {
    const int i = std::min(static_cast<int>(n * s[a]), n - 1);
    sub = n * sub + i;
    t[a] = std::min(n * s[a] - i, 1.0);
    spacing[a] = h[a] / n;
  }
  hermite_bases(t, spacing, B, dB);
  hermite_contract(n == 4 ? quarter_coef_[sub] : half_coef_[sub], B, dB, value, slope);
}

// Adds the cell's bubbles at s (B, dB: the Hermite bases there); their gradient to `slope` if
// given.
void CursorCore::bubbles_at(const std::array<double, 3>& s, const double (&B)[3][4],
                            const double (&dB)[3][4], std::array<double, 3>* value,
                            std::array<double, 9>* slope) const {
  // Along its axes a bubble is 16 t^2 (1 - t)^2 (Hermite) or the hat 1 - |2 t - 1|
  // (trilinear); across them the scheme's value basis of its side.
  const double* h = file_.impl().meta->spacing;
  double mb[3], dmb[3], v[3][2], dv[3][2];
  if (scheme_ == Scheme::kTrilinear) {
    trilinear_bubble_bases(s, h, mb, dmb, v, dv);
  } else {
    for (int a = 0; a < 3; ++a) {
      const double t = s[a], u = 1.0 - t;
      mb[a] = 16.0 * t * t * u * u;
      dmb[a] = 32.0 * t * u * (u - t) / h[a];
      v[a][0] = B[a][0], v[a][1] = B[a][2];
      dv[a][0] = dB[a][0], dv[a][1] = dB[a][2];
    }
  }
  add_bubbles(mb, dmb, v, dv, value, slope);
}

Force CursorCore::force(const std::array<double, 3>& probe) {
  Force out;
  std::array<double, 3> p_clamped{};
  const std::array<double, 3> s = locate(probe, &out.inside_grid, &p_clamped);
  double B[3][4], dB[3][4];  // the Hermite bases per axis and their derivatives
  hermite_bases(s, file_.impl().meta->spacing, B, dB);
  std::array<double, 3> value{};
  std::array<double, 9> slope{};    // d(value)/d(probe)
  std::array<double, 9> k_blend{};  // trilinear blend of the corners' stiffness
  // Trilinear (and outside the grid, either scheme): the corners' stiffness blended, and with
  // kTrilinear their forces; a fitted refined trilinear cell replaces both with its quarter
  // lattice's.
  const bool blended = scheme_ == Scheme::kTrilinear || !out.inside_grid;
  if (blended && !(fitted_ && refined_ && scheme_ == Scheme::kTrilinear))
    corner_blend(s, &value, &k_blend);
  if (!fitted_) fit_cell();
  if (refined_ && scheme_ == Scheme::kTrilinear) {
    if (deep_)
      eighth_trilinear_at(s, &value, &k_blend);
    else
      lattice_trilinear_at(s, 4, quarter_trilinear_.data(), &value, &k_blend);
  } else if (refined_ && deep_) {
    eighth_at(s, &value, &slope);
  } else if (refined_) {
    sub_cell_at(s, 4, &value, &slope);
  } else if (lattice_) {
    sub_cell_at(s, 2, &value, &slope);
  } else if (scheme_ == Scheme::kHermite) {
    hermite_contract(coef_, B, dB, &value, &slope);
  }
  if (num_bubbles_ > 0 && !refined_)
    bubbles_at(s, B, dB, &value, scheme_ == Scheme::kHermite && out.inside_grid ? &slope : nullptr);
  if (blended) slope = k_blend;
  // Hermite in a refined contact cell: where the half cells' force is the refined one, for the
  // displacements far from the sphere (Snapshot::sway_position, shown_position; near the onset
  // both forces before the blend, as the displacements are fitted through it).
  // (deform() needs the contact radius and the displacement slopes for it.)
  const bool shift = refined_ && scheme_ == Scheme::kHermite && out.inside_grid &&
                     file_.impl().meta->contact_radius > 0 && file_.impl().slopes &&
                     !(onset_ && clear_cell_);
  const std::array<double, 3> shown = shift ? shown_position(s, value) : s;
  const OnsetBlend onset = onset_ ? apply_onset(B, dB, s, &value, &slope) : OnsetBlend{};
  if (!out.inside_grid) {
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) value[r] += slope[3 * r + a] * (probe[a] - p_clamped[a]);
  }
  for (int r = 0; r < 3; ++r) out.value[r] = std::isfinite(value[r]) ? value[r] : 0.0;
  for (int r = 0; r < 9; ++r) out.stiffness[r] = std::isfinite(slope[r]) ? slope[r] : 0.0;
  ++calls_;
  publish(probe, out, s, shown, onset);
  return out;
}

std::int32_t CursorCore::anchor_configuration() const {
  int c = 0;
  for (int a = 0; a < 3; ++a) c |= (last_q_[a] - base_[a] >= 0.5 ? 1 : 0) << (2 - a);
  return corners_[c].configuration;
}

std::array<std::int32_t, 3> CursorCore::anchor_checkpoint() const {
  std::array<std::int32_t, 3> ijk{};
  for (int a = 0; a < 3; ++a) ijk[a] = base_[a] + (last_q_[a] - base_[a] >= 0.5 ? 1 : 0);
  return ijk;
}

}  // namespace playback
}  // namespace hapstate
