// What the refine-stage tests share: where a refinement row's point lies, and the cursor's force
// there walked to from rest (as a device would reach it).
#pragma once

#include "catalogue/catalogue.h"
#include "hapstate/playback.h"

#include <array>
#include <map>
#include <vector>

namespace hapstate::test_util {

// The position (mesh units) of each row's point: its cell's lowest check-point plus its quarter
// spacings, in the order of `rows`.
inline std::vector<std::array<double, 3>> refined_point_positions(
    Catalogue& cat, const PlaybackFile& file, const std::vector<RefinementPoint>& rows) {
  std::map<std::int64_t, Checkpoint> checkpoint_of;
  for (const Configuration& c : cat.read_all_configurations())
    checkpoint_of.emplace(c.id.value(), cat.read_checkpoint(c.checkpoint));
  const auto h = file.grid_spacing();
  std::vector<std::array<double, 3>> out;
  for (const RefinementPoint& r : rows) {
    const Checkpoint& cp = checkpoint_of.at(r.cell.value());
    const int q[3] = {r.point / 25, r.point / 5 % 5, r.point % 5};
    std::array<double, 3> p{};
    for (int a = 0; a < 3; ++a) p[a] = cp.position[a] + 0.25 * q[a] * h[a];
    out.push_back(p);
  }
  return out;
}

// The cursor reset to rest, walked to p in 10 straight steps; the force there.
inline Force force_walked_from_rest(HapticCursor& cursor, const PlaybackFile& file,
                                    const std::array<double, 3>& p) {
  const auto rest = file.rest_position();
  cursor.reset();
  for (int s = 1; s < 10; ++s)
    cursor.force({rest[0] + (p[0] - rest[0]) * s / 10, rest[1] + (p[1] - rest[1]) * s / 10,
                  rest[2] + (p[2] - rest[2]) * s / 10});
  return cursor.force(p);
}

}  // namespace hapstate::test_util
