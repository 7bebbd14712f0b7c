// Every haptic query of a walk timed on its own: a cursor walks the path of a hapstate-eval CSV
// (columns step, x, y, z, ...) with 10 straight sub-steps between its points, three times over
// (the first walk, which maps the file's pages, is not counted), per scheme; prints the median,
// the 99.9th percentile and the largest call, and the calls over 5 us (the cell and sub-cell
// entries: docs/playback.md, "Refined cells") with their median. docs/benchmarks.md, "Refined
// contact cells".
//   build/bench/query_walk FILE.bin EVAL.csv
#include "hapstate/playback.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace hapstate;
  if (argc != 3) {
    std::fprintf(stderr, "usage: query_walk FILE.bin EVAL.csv\n");
    return 2;
  }
  const PlaybackFile file(argv[1]);
  std::vector<std::array<double, 3>> path;
  std::ifstream in(argv[2]);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell;
    std::vector<double> v;
    while (v.size() < 4 && std::getline(cells, cell, ',')) v.push_back(std::stod(cell));
    if (v.size() == 4) path.push_back({v[1], v[2], v[3]});
  }
  if (path.size() < 2) {
    std::fprintf(stderr, "%s: fewer than 2 points\n", argv[2]);
    return 2;
  }
  using Clock = std::chrono::steady_clock;
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    HapticCursor cursor(file, scheme);
    std::vector<double> ns;
    for (int walk = 0; walk < 3; ++walk) {
      cursor.reset();
      for (std::size_t i = 1; i < path.size(); ++i)
        for (int k = 1; k <= 10; ++k) {
          std::array<double, 3> p{};
          for (int a = 0; a < 3; ++a)
            p[a] = path[i - 1][a] + (path[i][a] - path[i - 1][a]) * k / 10.0;
          const auto t0 = Clock::now();
          cursor.force(p);
          const auto t1 = Clock::now();
          if (walk > 0) ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
        }
    }
    std::sort(ns.begin(), ns.end());
    std::vector<double> slow;
    for (double t : ns)
      if (t > 5e3) slow.push_back(t);
    std::printf(
        "%-9s %zu calls: median %.0f ns, p99.9 %.0f ns, largest %.0f ns; %zu over 5 us (median "
        "%.0f ns)\n",
        scheme == Scheme::kHermite ? "hermite" : "trilinear", ns.size(), ns[ns.size() / 2],
        ns[ns.size() * 999 / 1000], ns.back(), slow.size(),
        slow.empty() ? 0.0 : slow[slow.size() / 2]);
  }
  return 0;
}
