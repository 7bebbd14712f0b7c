// The 26 grid directions from a check-point to its neighbours, numbered the same way in the
// catalogue, the playback file and the code. Direction d <-> offset (di, dj, dk) in
// {-1, 0, 1}^3 \ {(0,0,0)}: c = 9 (di+1) + 3 (dj+1) + (dk+1) runs 0..26 with 13 the centre;
// d = c for c < 13 and d = c - 1 above. So d = 0 is (-1,-1,-1), d = 12 is (0,0,-1), d = 13 is
// (0,0,+1), d = 25 is (+1,+1,+1), and opposite(d) = 25 - d.
#pragma once

#include <array>
#include <compare>
#include <cstdint>

namespace hapstate {

class Direction {
 public:
  static constexpr int kCount = 26;

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
