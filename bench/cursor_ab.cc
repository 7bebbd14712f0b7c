// Force-query timing of one build of the playback sources (bench/cursor_ab.sh compiles it against
// two commits' and runs them alternately): for each playback file given, and for a synthetic
// grab file it writes itself (tests/playback/synthetic.h), the best mean time per
// HapticCursor::force call over 5 passes of a seeded random walk of 100 000 steps of 0.02 mesh
// units inside the grid box, both schemes.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include "hapstate/playback.h"
#include "synthetic.h"
using namespace hapstate;
std::vector<std::array<double, 3>> walk(const PlaybackFile& f, int n, double step, unsigned seed) {
  auto o = f.grid_origin();
  auto h = f.grid_spacing();
  auto lo = f.grid_lo();
  auto d = f.grid_dims();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::array<double, 3> p = f.rest_position();
  std::vector<std::array<double, 3>> out;
  for (int k = 0; k < n; ++k) {
    std::array<double, 3> v{g(rng), g(rng), g(rng)};
    double m = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int a = 0; a < 3; ++a) {
      p[a] += step * v[a] / m;
      double a0 = o[a] + lo[a] * h[a], a1 = o[a] + (lo[a] + d[a] - 1) * h[a];
      p[a] = std::clamp(p[a], a0, a1);
    }
    out.push_back(p);
  }
  return out;
}
double time_walk(const PlaybackFile& f, Scheme s, const std::vector<std::array<double, 3>>& path) {
  double best = 1e9;
  for (int rep = 0; rep < 5; ++rep) {
    HapticCursor c(f, s);
    double sink = 0;
    auto t0 = std::chrono::steady_clock::now();
    for (const auto& p : path) sink += c.force(p).value[2];
    auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count() * 1e9 / path.size());
    if (sink == 12345.678) std::puts("");
  }
  return best;
}
int main(int argc, char** argv) {
  test_util::Field fld;
  const std::string syn_path = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                               "/cursor_ab_synthetic.bin";
  const char* syn = syn_path.c_str();
  playback::write_file(test_util::synthetic_content(fld, Eigen::Vector3d(0.5, 0.4, 0.6)), syn);
  for (int i = 1; i < argc + 1; ++i) {
    const char* file = i < argc ? argv[i] : syn;
    PlaybackFile f(file);
    auto path = walk(f, 100000, 0.02, 20261125);
    std::printf("%s: trilinear %.1f ns, hermite %.1f ns (best mean of 5 passes)\n", file,
                time_walk(f, Scheme::kTrilinear, path), time_walk(f, Scheme::kHermite, path));
  }
}
