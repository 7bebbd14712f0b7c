// What the refine-stage tests share: where a refinement row's point lies, and the cursor's force
// there walked to from rest (as a device would reach it).
#pragma once

#include "catalogue/catalogue.h"
#include "hapstate/playback.h"

#include <array>
#include <map>
#include <vector>

namespace hapstate::test_util {

// A row's point as steps from its cell's lowest corner: q and the steps per spacing n (4 for the
// quarter-spacing lattice, 8 for the eighth-spacing one, 16 for the sixteenth-spacing one:
// RefinementPoint::point).
struct LatticeStep {
  std::array<int, 3> q{};
  int n = 4;
};
inline LatticeStep lattice_step(int point) {
  if (point < kEighthFirstPoint) return {{point / 25, point / 5 % 5, point % 5}, 4};
  if (point < kSixteenthFirstPoint) {
    const int e = point - kEighthFirstPoint;
    return {{e / 81, e / 9 % 9, e % 9}, 8};
  }
  const int e = point - kSixteenthFirstPoint;
  return {{e / 289, e / 17 % 17, e % 17}, 16};
}

// The position (mesh units) of each row's point: its cell's lowest check-point plus its lattice
// steps, in the order of `rows`.
inline std::vector<std::array<double, 3>> refined_point_positions(
    Catalogue& cat, const PlaybackFile& file, const std::vector<RefinementPoint>& rows) {
  std::map<std::int64_t, Checkpoint> checkpoint_of;
  for (const Configuration& c : cat.read_all_configurations())
    checkpoint_of.emplace(c.id.value(), cat.read_checkpoint(c.checkpoint));
  const auto h = file.grid_spacing();
  std::vector<std::array<double, 3>> out;
  for (const RefinementPoint& r : rows) {
    const Checkpoint& cp = checkpoint_of.at(r.cell.value());
    const LatticeStep s = lattice_step(r.point);
    std::array<double, 3> p{};
    for (int a = 0; a < 3; ++a) p[a] = cp.position[a] + s.q[a] * h[a] / s.n;
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
