// Which cells the refine stage refines (docs/state-space.md, "Refined cells"): an estimate of
// how far the playback's Hermite interpolant on the half-spacing cells is from the force,
// from the data one recorded move holds.
#pragma once

#include <array>

namespace hapstate {

// One recorded move from a cell corner to another (an edge, a face diagonal or the body
// diagonal), parametrised by s in [0, 1]: the force at s = 0, 1/2, 1 and its derivative along
// the move (the stiffness times the move's vector, N per unit of s).
struct RecordedMove {
  std::array<double, 3> force[3];  // at s = 0, 1/2, 1
  std::array<double, 3> slope[3];  // d(force)/ds there
};

// The estimated error of the cubic Hermite pieces on [0, 1/2] and [1/2, 1] (what the playback
// interpolates along the move): the largest difference, over the components and s = 1/4, 3/4,
// between those pieces and the quintic Hermite through all six data. For a smooth force the
// quintic is the more accurate by a factor of h^2, so the difference estimates the pieces'
// error; it is 0 for a cubic force and exact for a quintic one. N.
double half_spacing_error(const RecordedMove& move);

}  // namespace hapstate
