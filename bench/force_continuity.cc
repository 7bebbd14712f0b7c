// The largest change of the haptic force over one small step (docs/playback.md, "Contact
// onset"): 300 seeded random straight lines across the grid box of a playback file, each walked
// in 20 000 steps by a cursor reset at its start, both schemes. Compile against the playback
// library and run on a file:
//   g++ -O2 -std=c++20 -Iinclude bench/force_continuity.cc build/libstate/libhapstate_playback.a \
//     -o /tmp/force_continuity && /tmp/force_continuity STATE/playback.bin
#include "hapstate/playback.h"

#include <cmath>
#include <cstdio>
#include <random>

using namespace hapstate;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s PLAYBACK_FILE\n", argv[0]);
    return 2;
  }
  PlaybackFile file(argv[1]);
  const auto o = file.grid_origin();
  const auto h = file.grid_spacing();
  const auto lo = file.grid_lo();
  const auto dims = file.grid_dims();
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0, largest = 0, step_length = 0;
    std::array<double, 3> at{};
    for (int line = 0; line < 300; ++line) {
      std::array<double, 3> a, b;
      for (int k = 0; k < 3; ++k) {
        a[k] = o[k] + (lo[k] + u(rng) * (dims[k] - 1)) * h[k];
        b[k] = o[k] + (lo[k] + u(rng) * (dims[k] - 1)) * h[k];
      }
      HapticCursor cursor(file, scheme);
      cursor.reset(a);
      std::array<double, 3> previous{};
      const int n = 20000;
      for (int s = 0; s <= n; ++s) {
        std::array<double, 3> p;
        for (int k = 0; k < 3; ++k) p[k] = a[k] + (b[k] - a[k]) * s / n;
        const Force f = cursor.force(p);
        double change = 0, norm = 0, length = 0;
        for (int k = 0; k < 3; ++k) {
          change += (f.value[k] - previous[k]) * (f.value[k] - previous[k]);
          norm += f.value[k] * f.value[k];
          length += (b[k] - a[k]) * (b[k] - a[k]) / (double(n) * n);
        }
        largest = std::max(largest, std::sqrt(norm));
        if (s > 0 && std::sqrt(change) > worst) {
          worst = std::sqrt(change);
          at = p;
          step_length = std::sqrt(length);
        }
        previous = f.value;
      }
    }
    std::printf(
        "%s: largest change over one step %.3g N (step %.3g mesh units, largest force %.3g N) "
        "at %.4f %.4f %.4f\n",
        scheme == Scheme::kHermite ? "hermite" : "trilinear", worst, step_length, largest, at[0],
        at[1], at[2]);
  }
}
