// hapstate-play's visual side: one frame = cursor snapshot + deform into a preallocated buffer
// (timed), then, every K-th frame, the surface and its displacement as a VTU file (not timed).
#pragma once

#include <hapstate/playback.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hapstate::play {

class FrameRenderer {
 public:
  // Preallocates the position buffer and room for `expected_frames` frame times.
  FrameRenderer(const PlaybackFile& file, const HapticCursor& cursor, std::int64_t expected_frames,
                std::filesystem::path frames_dir, int frame_every, double tick_rate);

  // A frame in two parts (fast mode lets the haptic loop go on in between): take() the
  // newest snapshot, finish() deforms and writes. Frame time: snapshot + deform.
  void take();
  void finish();
  int frames_written() const { return static_cast<int>(written_.size()); }
  std::vector<double>& frame_us() { return frame_us_; }
  // Writes frames.pvd listing the written frames in time (no-op without a frames directory).
  void write_collection() const;

 private:
  const PlaybackFile& file_;
  const HapticCursor& cursor_;
  std::filesystem::path dir_;
  int every_;
  double rate_;
  std::int64_t frame_ = 0;
  Snapshot snapshot_;
  double take_seconds_ = 0;
  std::vector<float> positions_;
  std::vector<double> frame_us_;
  std::vector<std::pair<double, std::string>> written_;
};

}  // namespace hapstate::play
