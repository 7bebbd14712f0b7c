#include "eval/region_path.h"

#include "playback/file_impl.h"
#include "util/error.h"

#include <cmath>

namespace hapstate {
namespace {

bool segment_in_region(const PlaybackFile& file, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const auto h = file.grid_spacing();
  const double hmin = std::min({h[0], h[1], h[2]});
  const int samples = 1 + static_cast<int>(std::ceil(10.0 * (b - a).norm() / hmin));
  for (int s = 0; s <= samples; ++s)
    if (!in_precomputed_region(file, a + (b - a) * (static_cast<double>(s) / samples))) return false;
  return true;
}

}  // namespace

bool in_precomputed_region(const PlaybackFile& file, const Eigen::Vector3d& p) {
  const PlaybackFile::Impl& f = file.impl();
  const playback::Meta& m = *f.meta;
  std::array<std::int32_t, 3> base{};
  for (int a = 0; a < 3; ++a) {
    const double q = (p[a] - m.origin[a]) / m.spacing[a];
    if (!(q >= m.lo[a] && q <= m.lo[a] + m.dims[a] - 1)) return false;
    base[a] = std::min(static_cast<std::int32_t>(std::floor(q)), f.last_cell(a));
  }
  for (int c = 0; c < 8; ++c) {
    // Along an axis with a single check-point the cell is flat: only its first corners count.
    if ((m.dims[0] == 1 && (c & 4)) || (m.dims[1] == 1 && (c & 2)) || (m.dims[2] == 1 && (c & 1))) continue;
    const std::int32_t g = f.point_index({base[0] + ((c >> 2) & 1), base[1] + ((c >> 1) & 1), base[2] + (c & 1)});
    if (g < 0 || f.checkpoints[2 * g + 1] <= 0) return false;
  }
  return true;
}

ProbePath precomputed_random_path(const PlaybackFile& file, int steps, double step_length,
                                  std::uint64_t seed) {
  const auto rest = file.rest_position();
  Eigen::Vector3d p(rest[0], rest[1], rest[2]);
  if (!in_precomputed_region(file, p))
    throw InputError(file.path().string() + ": the cell around the rest position is not precomputed "
                     "(some corner has no configuration): run hapstate-expand further");
  RandomDirections rng(seed);
  ProbePath path;
  for (int s = 0; s < steps; ++s) {
    double length = step_length;
    bool moved = false;
    while (!moved && length > 1e-6 * step_length) {
      for (int attempt = 0; attempt < 200 && !moved; ++attempt) {
        const Eigen::Vector3d next = p + length * rng.direction();
        if (segment_in_region(file, p, next)) {
          p = next;
          moved = true;
        }
      }
      length *= 0.5;
    }
    path.push_back(p);
  }
  return path;
}

}  // namespace hapstate
