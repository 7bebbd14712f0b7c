// Which cells the refine stage refines (docs/state-space.md, "Refined cells"): an estimate of
// how far the playback's Hermite interpolant on the half-spacing cells is from the force,
// from the data one recorded move holds.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

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

// A point of a refined cell's eighth-spacing lattice: the force and the haptic stiffness
// (row-major, N per mesh unit) there, when known (a corner, a move's midpoint, a solved point).
struct LatticeSample {
  std::array<double, 3> force{};
  std::array<double, 9> stiffness{};
  bool known = false;
};

// A refined cell's eighth-spacing lattice with one layer of its face neighbours' lattices around
// it: eighth steps -1 .. 9 along each axis from the cell's lowest corner, kHaloSide^3 samples at
// halo_index(i, j, k). Steps 0 .. 8 are the cell's own; a step -1 or 9 along one axis (the others
// in 0 .. 8) is the neighbour's across that face, its step 7 or 1; the rest is never read.
constexpr int kHaloSide = 11;
constexpr std::size_t halo_index(int i, int j, int k) {
  return std::size_t(kHaloSide * kHaloSide * (i + 1) + kHaloSide * (j + 1) + (k + 1));
}

// A cell's eighth-spacing lattice (`own`, 729 samples, 81 i + 9 j + k) with its face neighbours'
// next points (`neighbour[2 a]`: the lattice across the lower face along axis a (0: x), whose step
// 7 along a is our step -1; `[2 a + 1]`: the one across the upper face, whose step 1 is our step
// 9; null where there is none) as flag_eighth_cells reads it (kHaloSide^3 samples, halo_index;
// the halo's edges and corners unknown).
std::vector<LatticeSample> lattice_with_halo(
    const std::vector<LatticeSample>& own,
    const std::array<const std::vector<LatticeSample>*, 6>& neighbour);

// The eighth cells of a refined cell (64 i + 8 j + k, (i, j, k) the eighth steps of a cell's
// lowest corner) that refinement depth 3 refines, from the cell's eighth-spacing lattice and its
// neighbours' (`lattice`: kHaloSide^3 samples, halo_index) and `spacing` (mesh units): along
// every lattice line, each run of three neighbouring points (those crossing a face included) is
// a RecordedMove two eighth steps long whose half_spacing_error estimates the error of the eighth
// cells' Hermite pieces on its two edges; above `limit` (N) every eighth cell of this cell that
// has either edge is flagged. A run with an unknown sample flags nothing (a neighbour without an
// eighth-spacing lattice, or none). `largest`: the largest estimate (N), when not null. Throws
// std::invalid_argument unless `lattice` holds kHaloSide^3 samples.
std::vector<int> flag_eighth_cells(const std::vector<LatticeSample>& lattice,
                                   const std::array<double, 3>& spacing, double limit,
                                   double* largest = nullptr);

}  // namespace hapstate
