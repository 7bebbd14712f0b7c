#include "play/visual.h"

#include "io/surface_vtu.h"
#include "io/vtu_writer.h"

#include <chrono>
#include <cstdio>

namespace hapstate::play {

FrameRenderer::FrameRenderer(const PlaybackFile& file, const HapticCursor& cursor,
                             std::int64_t expected_frames, std::filesystem::path frames_dir,
                             int frame_every, double tick_rate)
    : file_(file),
      cursor_(cursor),
      dir_(std::move(frames_dir)),
      every_(frame_every),
      rate_(tick_rate),
      positions_(3 * static_cast<std::size_t>(file.num_view_nodes())) {
  frame_us_.reserve(static_cast<std::size_t>(expected_frames));
}

void FrameRenderer::take() {
  const auto t0 = std::chrono::steady_clock::now();
  cursor_.snapshot(&snapshot_);
  take_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void FrameRenderer::finish() {
  const auto t0 = std::chrono::steady_clock::now();
  deform(file_, snapshot_, positions_);
  const double seconds =
      take_seconds_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (frame_us_.size() < frame_us_.capacity()) frame_us_.push_back(1e6 * seconds);
  if (!dir_.empty() && frame_ % every_ == 0) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06lld.vtu", static_cast<long long>(frame_));
    write_surface_vtu(dir_ / name, positions_, file_.triangles(), file_.reference_positions());
    const double time = snapshot_.sequence > 0 ? (snapshot_.sequence - 1) / rate_ : 0.0;
    written_.emplace_back(time, name);
  }
  ++frame_;
}

void FrameRenderer::write_collection() const {
  if (!dir_.empty()) write_pvd(dir_ / "frames.pvd", written_);
}

}  // namespace hapstate::play
