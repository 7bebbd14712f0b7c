// One hapstate-play run: a haptic loop driving a HapticCursor along a TickPath (paced at the
// tick rate on CLOCK_MONOTONIC, or as fast as possible) and a visual thread at 60 Hz taking
// snapshots and deforming the surface into a preallocated buffer.
#pragma once

#include "play/tick_path.h"

#include <hapstate/playback.h>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace hapstate::play {

inline constexpr double kFrameRate = 60.0;  // Hz

struct SessionOptions {
  Scheme scheme = Scheme::kHermite;
  bool realtime = false;             // pace ticks and frames with absolute deadlines
  std::filesystem::path frames_dir;  // empty: no frame files
  int frame_every = 1;               // write every K-th frame
  bool record_ticks = false;         // keep t, x, y, z, fx, fy, fz per tick
};

struct SessionResult {
  std::int64_t force_calls = 0;
  std::vector<double> latency_us;  // per force call (steady_clock around the call)
  std::vector<double> frame_us;    // per frame: snapshot + deform
  std::int64_t missed_ticks = 0;   // realtime: force done after the next tick's deadline
  std::int64_t missed_frames = 0;  // realtime: frame done after the next frame's deadline
  std::int64_t outside_grid = 0;   // ticks with the probe outside the grid
  std::uint64_t cells_walked = 0;
  double max_force = 0;  // N
  double wall_seconds = 0;
  int frames_written = 0;
  std::vector<double> ticks;  // 7 per tick when recorded
};

SessionResult run_session(const PlaybackFile& file, const TickPath& path,
                          const SessionOptions& options);

}  // namespace hapstate::play
