// A grid direction from a check-point to one of its 26 neighbours, checked: the numbering is
// util/grid_direction.h's.
#pragma once

#include "util/grid_direction.h"

#include <array>
#include <compare>
#include <cstdint>

namespace hapstate {

class Direction {
 public:
  static constexpr int kCount = grid::kDirections;

  // Direction with index 0..25; throws std::out_of_range otherwise.
  explicit Direction(int index);
  // The direction with grid offset (di, dj, dk), each in {-1, 0, 1}, not all 0; throws
  // std::out_of_range otherwise.
  static Direction from_offset(int di, int dj, int dk);

  constexpr int index() const { return index_; }
  std::array<int, 3> offset() const;  // (di, dj, dk)
  Direction opposite() const { return Direction(kCount - 1 - index_); }
  int taxicab_length() const;  // 1 (face), 2 (edge) or 3 (corner) neighbour

  friend auto operator<=>(Direction, Direction) = default;

 private:
  std::uint8_t index_;
};

}  // namespace hapstate
