// The displacements of the view nodes for a snapshot (visual thread): stored arrays blended with
// scalar weights. Trilinear: the 8 corners' displacements. Hermite: the same tensor-product cubic
// as the force (docs/playback.md), with each corner's displacement slopes d u / d p as the
// derivatives and the cross derivatives estimated from the slopes of the corners on the same
// cell face; an extended corner's displacements are its source's extended by the source's
// slopes, a secant corner's (a free check-point beside the contact onset, cursor_onset.cc) its
// source's scaled. Where the snapshot marks stored midpoint displacements (Snapshot::midpoint)
// the cubic is that of the half-spacing cell the probe is in, as the force's. Just past the
// onset the depth model is blended in (Snapshot::onset_weight), and a midpoint inside the blend
// is fitted through it (Snapshot::midpoint_blend). In a refined contact cell the nodes far from
// the sphere are interpolated at Snapshot::sway_position. The weights are computed once per
// frame; the arrays are streamed once (a block of nodes between near and far: twice).
#include "playback/file_impl.h"
#include "playback/hermite_bases.h"

#include <algorithm>
#include <cmath>

namespace hapstate {
namespace {

// The arrays to add and their weights, one entry per distinct (configuration, array).
class Blend {
 public:
  static constexpr int kMax = 80;
  explicit Blend(double scale) : scale_(scale) {}
  void set_scale(double scale) { scale_ = scale; }  // of the weights added from now on
  // kind 0: the displacements of configuration k, kind 1 + a: its slopes along axis a; kind 4:
  // the displacements of stored midpoint k (Snapshot::midpoint - 1), kind 5 + a: their slopes.
  void add(std::int32_t k, int kind, double w) {
    w *= scale_;
    if (k < 0 || w == 0.0) return;  // -1: a zero corner, nothing to add
    for (int j = 0; j < count_; ++j)
      if (config_[j] == k && kind_[j] == kind) {
        weight_[j] += w;
        return;
      }
    // Cannot happen: 8 corners x 4 arrays, 7 midpoints x 4 and 8 depth sources at most.
    if (count_ == kMax) return;
    config_[count_] = k, kind_[count_] = kind, weight_[count_++] = w;
  }
  // out += Σ weight x array, in blocks so that out stays in cache while the arrays stream by.
  void apply(const PlaybackFile::Impl& f, std::span<float> out) const {
    Sources s(*this, f);
    const std::size_t m = std::min(s.n, out.size());
    for (std::size_t begin = 0; begin < m; begin += kBlock)
      add_block(s, begin, std::min(m, begin + kBlock), out.data(), 0);
  }
  // out += near + factor(node) x (far - near), per block of nodes: a block whose factors are all
  // 0 streams near's arrays only, one whose factors are all 1 far's only.
  template <class Factor>
  static void apply_mixed(const PlaybackFile::Impl& f, std::span<float> out, const Blend& near,
                          const Blend& far, Factor factor) {
    const Sources sn(near, f), sf(far, f);
    const std::size_t m = std::min(sn.n, out.size());
    float mix[kBlock / 3 + 1], at_near[kBlock], at_far[kBlock];
    for (std::size_t begin = 0; begin < m; begin += kBlock) {
      const std::size_t end = std::min(m, begin + kBlock);
      const std::size_t first = begin / 3, last = (end - 1) / 3;
      float lo = 1, hi = 0;
      for (std::size_t node = first; node <= last; ++node) {
        mix[node - first] = factor(node);
        lo = std::min(lo, mix[node - first]), hi = std::max(hi, mix[node - first]);
      }
      if (hi == 0) {
        add_block(sn, begin, end, out.data(), 0);
      } else if (lo == 1) {
        add_block(sf, begin, end, out.data(), 0);
      } else {
        std::fill_n(at_near, end - begin, 0.0f);
        std::fill_n(at_far, end - begin, 0.0f);
        add_block(sn, begin, end, at_near, begin);
        add_block(sf, begin, end, at_far, begin);
        for (std::size_t i = begin; i < end; ++i) {
          const float a = at_near[i - begin], b = at_far[i - begin];
          out[i] += a + mix[i / 3 - first] * (b - a);
        }
      }
    }
  }

 private:
  static constexpr std::size_t kBlock = 4096;
  struct Sources {
    Sources(const Blend& b, const PlaybackFile::Impl& f)
        : n(3 * static_cast<std::size_t>(f.meta->num_view_nodes)), count(b.count_) {
      for (int j = 0; j < count; ++j) {
        const std::size_t k = static_cast<std::size_t>(b.config_[j]);
        src[j] = b.kind_[j] == 0  ? f.displacements + n * k
                 : b.kind_[j] < 4 ? f.slopes + n * (3 * k + b.kind_[j] - 1)
                                  : f.midpoint_displacements + n * (4 * k + b.kind_[j] - 4);
        w[j] = static_cast<float>(b.weight_[j]);
      }
    }
    std::size_t n;
    int count;
    const float* src[kMax];
    float w[kMax];
  };
  // o[i - base] += Σ w x src[i] for i in [begin, end). Eight arrays per pass over a block (the
  // output block is loaded and stored once per eight arrays and stays in L1 between passes; 4x
  // faster than one array per pass on 50 000 nodes).
  static void add_block(const Sources& s, std::size_t begin, std::size_t end, float* o,
                        std::size_t base) {
    const float* const* src = s.src;
    const float* w = s.w;
    const std::size_t length = end - begin;
    int j = 0;
    for (; j + 8 <= s.count; j += 8) {
      const float* __restrict a0 = src[j] + begin;
      const float* __restrict a1 = src[j + 1] + begin;
      const float* __restrict a2 = src[j + 2] + begin;
      const float* __restrict a3 = src[j + 3] + begin;
      const float* __restrict a4 = src[j + 4] + begin;
      const float* __restrict a5 = src[j + 5] + begin;
      const float* __restrict a6 = src[j + 6] + begin;
      const float* __restrict a7 = src[j + 7] + begin;
      float* __restrict dst = o + (begin - base);
      const float* wj = w + j;
      for (std::size_t i = 0; i < length; ++i)
        dst[i] += (wj[0] * a0[i] + wj[1] * a1[i] + wj[2] * a2[i] + wj[3] * a3[i]) +
                  (wj[4] * a4[i] + wj[5] * a5[i] + wj[6] * a6[i] + wj[7] * a7[i]);
    }
    for (; j < s.count; ++j) {
      const float* __restrict a = src[j] + begin;
      float* __restrict dst = o + (begin - base);
      const float wa = w[j];
      for (std::size_t i = 0; i < length; ++i) dst[i] += wa * a[i];
    }
  }

  std::int32_t config_[kMax];
  int kind_[kMax];
  double weight_[kMax];
  int count_ = 0;
  double scale_ = 1;
};

std::array<int, 3> corner_side(int c) { return {(c >> 2) & 1, (c >> 1) & 1, c & 1}; }

// Corner c of a snapshot as sums of stored arrays: its displacements (value) and their slope
// along an axis, each added to a Blend with a weight.
class Corners {
 public:
  Corners(const PlaybackFile::Impl& f, const Snapshot& s) : f_(f), s_(s) {
    for (int c = 0; c < 8; ++c) {
      config_[c] = s.corner_configuration[c];
      if (config_[c] >= f.meta->num_configurations) config_[c] = -1;
    }
  }
  bool secant(int c) const { return (s_.secant_corners >> c) & 1; }
  // The source's displacements plus (extended corner) its slopes times the shift; a secant
  // corner: the source's displacements times secant[0].
  void add_value(int c, double w, Blend* blend) const { add_value(c, w, true, blend); }
  void add_value(int c, double w, bool with_shift, Blend* blend) const {
    if (secant(c)) return blend->add(config_[c], 0, w * s_.secant[c][0]);
    blend->add(config_[c], 0, w);
    if (!with_shift) return;
    for (int a = 0; a < 3; ++a)
      blend->add(config_[c], 1 + a, w * s_.corner_shift[c][a] * f_.meta->spacing[a]);
  }
  // The slope along axis a: the source's; a secant corner: its displacements x secant[1 + a].
  void add_slope(int c, int a, double w, Blend* blend) const {
    if (secant(c)) return blend->add(config_[c], 0, w * s_.secant[c][1 + a]);
    blend->add(config_[c], 1 + a, w);
  }

 private:
  const PlaybackFile::Impl& f_;
  const Snapshot& s_;
  std::int32_t config_[8];
};

void add_trilinear(const PlaybackFile::Impl& f, const Snapshot& s, Blend* blend) {
  const Corners corners(f, s);
  for (int c = 0; c < 8; ++c) corners.add_value(c, s.weight[c], false, blend);
}

// The weights of a Hermite cell of widths h whose 8 corners' values and slopes `points` adds
// (add_value(c, w, blend), add_slope(c, a, w, blend)), at cell position t, times `scale`: its
// value, or with axis >= 0 its derivative along that axis. The cross derivatives of each face
// pair (a, b) are half the difference quotients of the slopes along a across b and along b
// across a (the force's estimate, cell_math.h).
template <class Points>
void add_hermite(const Points& points, const std::array<double, 3>& t, const double* h, int axis,
                 double scale, Blend* blend) {
  double value[3][4], derivative[3][4];
  playback::hermite_bases(
      {std::clamp(t[0], 0.0, 1.0), std::clamp(t[1], 0.0, 1.0), std::clamp(t[2], 0.0, 1.0)}, h,
      value, derivative);
  const double(&B0)[4] = axis == 0 ? derivative[0] : value[0];
  const double(&B1)[4] = axis == 1 ? derivative[1] : value[1];
  const double(&B2)[4] = axis == 2 ? derivative[2] : value[2];
  const double* B[3] = {B0, B1, B2};
  static constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int c = 0; c < 8; ++c) {
    const auto o = corner_side(c);
    auto weight = [&](int kx, int ky, int kz) {
      return scale * B[0][2 * o[0] + kx] * B[1][2 * o[1] + ky] * B[2][2 * o[2] + kz];
    };
    points.add_value(c, weight(0, 0, 0), blend);
    for (int a = 0; a < 3; ++a) {
      int k[3] = {0, 0, 0};
      k[a] = 1;
      points.add_slope(c, a, weight(k[0], k[1], k[2]), blend);
    }
    for (const auto& pair : kPair) {
      const int a = pair[0], b = pair[1];
      int k[3] = {0, 0, 0};
      k[a] = k[b] = 1;
      const double w = 0.5 * weight(k[0], k[1], k[2]);
      const double sa = o[a] ? 1.0 : -1.0, sb = o[b] ? 1.0 : -1.0;
      points.add_slope(c, a, w * sb / h[b], blend);
      points.add_slope(c ^ (4 >> b), a, -w * sb / h[b], blend);
      points.add_slope(c, b, w * sa / h[a], blend);
      points.add_slope(c ^ (4 >> a), b, -w * sa / h[a], blend);
    }
  }
}

// Whether Snapshot::midpoint code names a midpoint the file stores (a snapshot from elsewhere,
// e.g. the C interface, is not trusted: any other code means none).
bool stored_midpoint(const PlaybackFile::Impl& f, std::int32_t code) {
  if (!f.midpoint_mask || code <= 0) return false;
  const std::int64_t k = code - 1;
  if (k >= std::int64_t{playback::kMidpointDirections} * f.meta->num_configurations) return false;
  return (f.midpoint_mask[k / playback::kMidpointDirections] >>
          (k % playback::kMidpointDirections)) &
         1;
}

// The corners of one half-spacing cell (`sub`, bits x y z as the corners) as points of
// add_hermite: the cell corner among them takes its data (Corners), a midpoint the stored
// displacements and slopes (Snapshot::midpoint), any other midpoint the whole cell's Hermite
// interpolant's value and derivative there. With every midpoint stored this is the Hermite
// interpolant of a grid of half the spacing (the cursor's force takes its cross derivatives from
// the whole lattice instead, cell_lattice.h; here they come from the half cell's own corners, whose
// arrays are the only ones the frame streams).
class HalfCellPoints {
 public:
  HalfCellPoints(const PlaybackFile::Impl& f, const Corners& corners, const Snapshot& s,
                 const double* h, int sub)
      : f_(f), corners_(corners), s_(s), h_(h), sub_(corner_side(sub)) {}
  void add_value(int c, double w, Blend* blend) const { add(c, -1, w, blend); }
  void add_slope(int c, int a, double w, Blend* blend) const { add(c, a, w, blend); }

 private:
  // The value (axis -1) or the slope along `axis` at point c, times w.
  void add(int c, int axis, double w, Blend* blend) const {
    if (w == 0.0) return;
    const auto o = corner_side(c);
    const int L[3] = {sub_[0] + o[0], sub_[1] + o[1], sub_[2] + o[2]};
    if (L[0] % 2 == 0 && L[1] % 2 == 0 && L[2] % 2 == 0) {
      const int corner = ((L[0] / 2) << 2) | ((L[1] / 2) << 1) | (L[2] / 2);
      if (axis < 0) return corners_.add_value(corner, w, blend);
      return corners_.add_slope(corner, axis, w, blend);
    }
    const int point = 9 * L[0] + 3 * L[1] + L[2];
    const std::int32_t code = s_.midpoint[point];
    if (stored_midpoint(f_, code)) {
      const std::array<double, 6>& onset = s_.midpoint_blend[point];
      if (onset[0] == 0.0) return blend->add(code - 1, axis < 0 ? 4 : 5 + axis, w);
      if (valid_blend(onset)) return add_through_blend(code, L, axis, w, onset, blend);
      // A damaged or foreign blend: the point as if not stored (below).
    }
    const std::array<double, 3> at = {0.5 * L[0], 0.5 * L[1], 0.5 * L[2]};
    add_hermite(corners_, at, h_, axis, w, blend);
  }

  // What the cursor publishes: all finite, R in [1/4, 1], dR/dd >= 0, depth > 0.
  static bool valid_blend(const std::array<double, 6>& onset) {
    for (double v : onset)
      if (!std::isfinite(v)) return false;
    return onset[0] >= 0.25 && onset[0] <= 1.0 && onset[1] >= 0.0 && onset[2] > 0.0;
  }

  // Near the contact onset deform() returns R U + (1 - R) D, U this interpolant and D the depth
  // model d sum_c w_c q_c u(source_c) (Snapshot::onset_weight = 1 - R at the probe). A stored
  // midpoint u_m, du_m is fitted through that blend as the cursor fits its force: with R, d and
  // their gradients at the point, U_m = (u_m - (1 - R) D_m) / R and
  // dU_m = (du_m - (1 - R) dD_m - (u_m - D_m) dR / R) / R, so the blend returns u_m and du_m there.
  void add_through_blend(std::int32_t code, const int (&L)[3], int axis, double w,
                         const std::array<double, 6>& onset, Blend* blend) const {
    const double R = onset[0], dR_dd = onset[1], d = onset[2];
    std::int32_t source[8];  // the depth model's arrays (-1: none; a damaged index: none)
    for (int c = 0; c < 8; ++c)
      source[c] = s_.depth_source[c] < f_.meta->num_configurations ? s_.depth_source[c] : -1;
    double tw[8], dtw[8];  // trilinear weights of the corners at the point, and along `axis`
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_side(c);
      tw[c] = 1.0;
      dtw[c] = axis < 0 ? 0.0 : (o[axis] ? 1.0 : -1.0) / h_[axis];
      for (int b = 0; b < 3; ++b) {
        const double t = 0.5 * L[b], lin = o[b] ? t : 1.0 - t;
        tw[c] *= lin;
        if (b != axis) dtw[c] *= lin;
      }
    }
    if (axis < 0) {
      blend->add(code - 1, 4, w / R);
      for (int c = 0; c < 8; ++c)
        blend->add(source[c], 0, -w * (1.0 - R) / R * d * tw[c] * s_.per_depth[c]);
      return;
    }
    const double dd = onset[3 + axis], dR = dR_dd * dd;
    blend->add(code - 1, 5 + axis, w / R);
    blend->add(code - 1, 4, -w * dR / (R * R));
    for (int c = 0; c < 8; ++c)
      blend->add(source[c], 0,
                 w * s_.per_depth[c] *
                     (-(1.0 - R) / R * (dd * tw[c] + d * dtw[c]) + dR / (R * R) * d * tw[c]));
  }

  const PlaybackFile::Impl& f_;
  const Corners& corners_;
  const Snapshot& s_;
  const double* h_;
  std::array<int, 3> sub_;
};

// The Hermite cell at cell position `at` (the probe's, or Snapshot::sway_position).
void add_cell_hermite(const PlaybackFile::Impl& f, const Snapshot& s,
                      const std::array<double, 3>& at, Blend* blend) {
  const Corners corners(f, s);
  const double* h = f.meta->spacing;
  const bool midpoints = std::any_of(s.midpoint.begin(), s.midpoint.end(),
                                     [&](std::int32_t code) { return stored_midpoint(f, code); });
  if (!midpoints) return add_hermite(corners, at, h, -1, 1.0, blend);
  int sub = 0;
  std::array<double, 3> t{};
  const double half[3] = {0.5 * h[0], 0.5 * h[1], 0.5 * h[2]};
  for (int a = 0; a < 3; ++a) {
    const double p = std::clamp(at[a], 0.0, 1.0);
    const int side = p >= 0.5 ? 1 : 0;
    sub |= side << (2 - a);
    t[a] = 2.0 * p - side;
  }
  add_hermite(HalfCellPoints(f, corners, s, h, sub), t, half, -1, 1.0, blend);
}

// Just past the contact onset: the depth model's share.
void add_depth_model(const PlaybackFile::Impl& f, const Snapshot& s, Blend* blend) {
  blend->set_scale(s.onset_weight * s.onset_depth);
  for (int c = 0; c < 8; ++c)
    if (s.onset_weight != 0.0 && s.depth_source[c] < f.meta->num_configurations)
      blend->add(s.depth_source[c], 0, s.weight[c] * s.per_depth[c]);
}

// Hermite in a refined contact cell (Snapshot::sway_position): the nodes far from the sphere take
// the cell's interpolant at sway_position, those near it at cell_position, blended by the
// distance d of the node at rest from the probe, smoothly from 2 radii to 4 (docs/playback.md,
// "Refined cells"). A block of nodes all near or all far streams one set of arrays, as elsewhere.
bool blend_sway(const PlaybackFile::Impl& f, const Snapshot& s, std::span<float> out) {
  const double r = f.meta->contact_radius;
  if (s.sway_position == s.cell_position || !(r > 0) || !f.reference) return false;
  // A snapshot from elsewhere is not trusted: the cursor's point lies in the cell, within a
  // quarter of the smallest spacing of the probe.
  const double* h = f.meta->spacing;
  const double reach = 0.25 * std::min({h[0], h[1], h[2]}) * (1 + 1e-9);
  double moved_by = 0;
  for (int a = 0; a < 3; ++a) {
    const double t = s.sway_position[a];
    if (!(t >= 0.0 && t <= 1.0)) return false;
    moved_by += std::pow((t - s.cell_position[a]) * h[a], 2);
  }
  if (!(std::sqrt(moved_by) <= reach)) return false;
  Blend near(1.0 - s.onset_weight), far(1.0 - s.onset_weight);
  add_cell_hermite(f, s, s.cell_position, &near);
  add_depth_model(f, s, &near);
  add_cell_hermite(f, s, s.sway_position, &far);
  add_depth_model(f, s, &far);
  const float* x = f.reference;
  const double inner = 2 * r, outer = 4 * r;
  Blend::apply_mixed(f, out, near, far, [&](std::size_t node) {
    const double dx = x[3 * node] - s.probe[0], dy = x[3 * node + 1] - s.probe[1],
                 dz = x[3 * node + 2] - s.probe[2];
    const double t =
        std::clamp((std::sqrt(dx * dx + dy * dy + dz * dz) - inner) / (outer - inner), 0.0, 1.0);
    return static_cast<float>(t * t * (3.0 - 2.0 * t));
  });
  return true;
}

void blend(const PlaybackFile::Impl& f, const Snapshot& s, std::span<float> out) {
  const bool hermite = s.scheme == Scheme::kHermite && f.slopes;
  if (hermite && blend_sway(f, s, out)) return;
  Blend blend(1.0 - s.onset_weight);
  if (hermite)
    add_cell_hermite(f, s, s.cell_position, &blend);
  else
    add_trilinear(f, s, &blend);
  add_depth_model(f, s, &blend);
  blend.apply(f, out);
}

}  // namespace

void displacements(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out) {
  std::fill(out.begin(), out.end(), 0.0f);
  blend(file.impl(), snapshot, out);
}

void deform(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out) {
  const auto ref = file.reference_positions();
  std::copy_n(ref.begin(), std::min(ref.size(), out.size()), out.begin());
  blend(file.impl(), snapshot, out);
}

}  // namespace hapstate
