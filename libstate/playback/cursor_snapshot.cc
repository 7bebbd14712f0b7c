// The cursor's snapshot buffer: what force() publishes for the visual thread, a wait-free
// triple buffer (docs/playback.md, "Snapshots").
#include "playback/cursor_core.h"

#include "playback/cell_math.h"

#include <algorithm>

namespace hapstate::playback {

namespace {

constexpr std::uint32_t kFresh = 4;  // triple buffer: the middle slot holds an unread snapshot

}  // namespace

void CursorCore::publish(const std::array<double, 3>& probe, const Force& f,
                         const std::array<double, 3>& s, const std::array<double, 3>& shown,
                         const OnsetBlend& onset) {
  Snapshot& slot = slots_[back_];
  slot.sequence = calls_;
  slot.probe = probe;
  slot.force = f.value;
  slot.cell_position = s;
  slot.sway_position = shown;
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

void CursorCore::snapshot(Snapshot* out) const {
  if (middle_.load(std::memory_order_acquire) & kFresh)
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & 3u;
  *out = slots_[front_];
}

static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

}  // namespace hapstate::playback
