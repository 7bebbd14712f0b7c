// The 26 grid directions from a check-point to its neighbours: the one definition of their
// numbering, used by the catalogue (catalogue/direction.h wraps it in a checked type), the
// playback file and its writer, and the cursor. Direction d <-> offset (di, dj, dk) in
// {-1, 0, 1}^3 \ {(0,0,0)}: c = 9 (di+1) + 3 (dj+1) + (dk+1) runs 0..26 with 13 the centre;
// d = c for c < 13 and d = c - 1 above. So d = 0 is (-1,-1,-1), d = 12 is (0,0,-1), d = 13 is
// (0,0,+1), d = 25 is (+1,+1,+1), and the opposite of d is 25 - d. A configuration's moves are
// stored as 26 entries in this order (the catalogue's transitions, the playback file's table).
#pragma once

#include <array>

namespace hapstate::grid {

constexpr int kDirections = 26;

// The index of offset (di, dj, dk), each in {-1, 0, 1} and not all 0 (not checked).
constexpr int direction_index(int di, int dj, int dk) {
  const int c = 9 * (di + 1) + 3 * (dj + 1) + (dk + 1);
  return c < 13 ? c : c - 1;
}
constexpr int direction_index(const std::array<int, 3>& o) {
  return direction_index(o[0], o[1], o[2]);
}

// The offset of direction d in 0..25 (not checked).
constexpr std::array<int, 3> direction_offset(int d) {
  const int c = d < 13 ? d : d + 1;
  return {c / 9 - 1, (c / 3) % 3 - 1, c % 3 - 1};
}

static_assert(direction_index(-1, -1, -1) == 0 && direction_index(0, 0, -1) == 12 &&
              direction_index(0, 0, 1) == 13 && direction_index(1, 1, 1) == kDirections - 1);
static_assert(direction_offset(13)[2] == 1 && direction_offset(12)[2] == -1);

}  // namespace hapstate::grid
