#include "catalogue/direction.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace hapstate {

Direction::Direction(int index) : index_(0) {
  if (index < 0 || index >= kCount) {
    throw std::out_of_range("Direction: index " + std::to_string(index) + " is not in 0..25");
  }
  index_ = static_cast<std::uint8_t>(index);
}

Direction Direction::from_offset(int di, int dj, int dk) {
  const auto unit = [](int v) { return v >= -1 && v <= 1; };
  if (!unit(di) || !unit(dj) || !unit(dk) || (di == 0 && dj == 0 && dk == 0)) {
    throw std::out_of_range("Direction: offset (" + std::to_string(di) + ", " + std::to_string(dj) +
                            ", " + std::to_string(dk) + ") is not a neighbour");
  }
  return Direction(grid::direction_index(di, dj, dk));
}

std::array<int, 3> Direction::offset() const { return grid::direction_offset(index_); }

int Direction::taxicab_length() const {
  const auto o = offset();
  return std::abs(o[0]) + std::abs(o[1]) + std::abs(o[2]);
}

}  // namespace hapstate
