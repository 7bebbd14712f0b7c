// PRIVATE to the playback module: the Hermite data at the points of a cell's lattice (the
// arithmetic on it: cell_lattice.h).
#pragma once

namespace hapstate::playback {

// The data at the points of a cell's lattice with N points per axis (N = 3: the half-spacing
// lattice, 5: a refined cell's quarter-spacing one, 9: its eighth-spacing one): value, gradient
// (row-major, 3 r + a) and the cross derivatives [r][pair] (kPair).
template <int N>
struct Lattice {
  double value[N][N][N][3];
  double gradient[N][N][N][9];
  double cross[N][N][N][3][3];
};

}  // namespace hapstate::playback
