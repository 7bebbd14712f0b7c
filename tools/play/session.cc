#include "play/session.h"

#include "play/visual.h"

#include <time.h>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <exception>
#include <thread>

namespace hapstate::play {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::int64_t kStop = -2;

std::int64_t monotonic_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t deadline) {
  timespec ts{static_cast<time_t>(deadline / 1'000'000'000),
              static_cast<long>(deadline % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// Shared between the haptic loop and the visual thread.
struct Sync {
  std::atomic<std::int64_t> request{-1};  // fast mode: frame the haptic loop asks for
  std::atomic<std::int64_t> taken{-1};    // fast mode: last frame whose snapshot was taken
  std::atomic<bool> done{false};          // realtime mode: the haptic loop finished
  std::exception_ptr error;               // the visual thread's failure (read after join)
};

// Fast mode: frame f shows the state right after the tick the haptic loop asked for it at.
void visual_fast(FrameRenderer& renderer, Sync& sync) {
  std::int64_t last = -1;
  for (;;) {
    sync.request.wait(last);
    const std::int64_t f = sync.request.load();
    if (f == kStop) return;
    last = f;
    if (!sync.error) {
      try {
        renderer.take();
      } catch (...) {
        sync.error = std::current_exception();
      }
    }
    sync.taken.store(f);
    sync.taken.notify_one();
    if (!sync.error) {
      try {
        renderer.finish();
      } catch (...) {
        sync.error = std::current_exception();
      }
    }
  }
}

void visual_realtime(FrameRenderer& renderer, Sync& sync, std::int64_t start_ns,
                     std::int64_t* missed) {
  const double period = 1e9 / kFrameRate;
  for (std::int64_t f = 0; !sync.done.load(std::memory_order_relaxed); ++f) {
    const auto deadline = start_ns + static_cast<std::int64_t>(std::llround(f * period));
    sleep_until_ns(deadline);
    try {
      renderer.take();
      renderer.finish();
    } catch (...) {
      sync.error = std::current_exception();
      return;
    }
    if (monotonic_ns() > deadline + static_cast<std::int64_t>(period)) ++*missed;
  }
}

}  // namespace

SessionResult run_session(const PlaybackFile& file, const TickPath& path, const SessionOptions& o) {
  SessionResult r;
  const std::int64_t n = path.num_ticks();
  const double rate = path.rate();
  r.latency_us.resize(static_cast<std::size_t>(n));
  if (o.record_ticks) r.ticks.resize(7 * static_cast<std::size_t>(n));
  HapticCursor cursor(file, o.scheme);
  // The device starts at the path's first point with the body at rest (a contact probe
  // anywhere clear of the body; the grab probe walks there from rest).
  cursor.reset(TickPath::Sampler(path).position(0));
  const auto expected_frames = static_cast<std::int64_t>(std::ceil(n / rate * kFrameRate)) + 4;
  FrameRenderer renderer(file, cursor, expected_frames, o.frames_dir, o.frame_every, rate);
  Sync sync;
  const std::int64_t tick_ns = std::llround(1e9 / rate);
  const std::int64_t start_ns = monotonic_ns() + 2'000'000;  // both threads start together
  std::thread visual(o.realtime ? std::thread(visual_realtime, std::ref(renderer), std::ref(sync),
                                              start_ns, &r.missed_frames)
                                : std::thread(visual_fast, std::ref(renderer), std::ref(sync)));
  TickPath::Sampler sampler(path);
  const double frame_ticks = rate / kFrameRate;
  std::int64_t next_frame = 0;
  const auto wall0 = Clock::now();
  for (std::int64_t k = 0; k < n; ++k) {
    const std::array<double, 3> p = sampler.position(k);
    if (o.realtime) sleep_until_ns(start_ns + k * tick_ns);
    const auto t0 = Clock::now();
    const Force f = cursor.force(p);
    const auto t1 = Clock::now();
    r.latency_us[static_cast<std::size_t>(k)] =
        std::chrono::duration<double, std::micro>(t1 - t0).count();
    if (o.realtime && monotonic_ns() > start_ns + (k + 1) * tick_ns) ++r.missed_ticks;
    const double magnitude = std::hypot(f.value[0], f.value[1], f.value[2]);
    r.max_force = std::max(r.max_force, magnitude);
    r.outside_grid += f.inside_grid ? 0 : 1;
    if (o.record_ticks) {
      double* row = &r.ticks[7 * static_cast<std::size_t>(k)];
      row[0] = k / rate;
      for (int a = 0; a < 3; ++a) row[1 + a] = p[a], row[4 + a] = f.value[a];
    }
    if (!o.realtime && k >= std::ceil(next_frame * frame_ticks - 1e-9)) {
      sync.request.store(next_frame);
      sync.request.notify_one();
      for (std::int64_t t = sync.taken.load(); t < next_frame; t = sync.taken.load())
        sync.taken.wait(t);
      ++next_frame;
    }
  }
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  r.force_calls = n;
  r.cells_walked = cursor.cells_walked();
  sync.done.store(true);
  sync.request.store(kStop);
  sync.request.notify_one();
  visual.join();
  if (sync.error) std::rethrow_exception(sync.error);
  renderer.write_collection();
  r.frame_us = std::move(renderer.frame_us());
  r.frames_written = renderer.frames_written();
  return r;
}

}  // namespace hapstate::play
