// libFuzzer harness: the playback loader on damaged files (the O(1) checks, then verify()),
// and the cursor on whatever loaded with or without verify(): it must never read out of bounds
// or return a non-finite force (docs/playback.md).
#include "fuzz_util.h"
#include "hapstate/playback.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapstate;
  const auto file = fuzz::write_scratch("fuzz.bin", data, size);
  try {
    PlaybackFile playback(file);
    try {
      playback.verify();
    } catch (const std::runtime_error&) {
      // The cursor must stay safe on a file that failed verify() too.
    }
    for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
      HapticCursor cursor(playback, scheme);
      const auto o = playback.grid_origin();
      const auto h = playback.grid_spacing();
      for (int n = 0; n < 64; ++n) {
        const double t = 0.37 * n;
        const std::array<double, 3> p{o[0] + h[0] * 3 * std::sin(t),
                                      o[1] + h[1] * 3 * std::cos(1.3 * t),
                                      o[2] + h[2] * 3 * std::sin(0.7 * t)};
        const Force f = cursor.force(p);
        for (double v : f.value)
          if (!std::isfinite(v)) std::abort();
        for (double v : f.stiffness)
          if (!std::isfinite(v)) std::abort();
      }
      cursor.reset(o);
      Snapshot s;
      cursor.snapshot(&s);
      std::vector<float> positions(3 * static_cast<std::size_t>(playback.num_view_nodes()));
      deform(playback, s, positions);
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
