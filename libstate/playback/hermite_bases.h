// PRIVATE to the playback module: the cubic Hermite bases the cursor (force) and deform()
// (displacements) share.
#pragma once

#include <array>

namespace hapstate::playback {

// Per axis a the 4 cubic Hermite bases at cell position s[a] in [0, 1], B[a][2 o + k] (o the
// corner side; k 0 the value basis, 1 the derivative basis in physical units, spacing h[a]), and
// their derivatives dB with respect to the probe coordinate.
inline void hermite_bases(const std::array<double, 3>& s, const double* h, double (&B)[3][4],
                          double (&dB)[3][4]) {
  for (int a = 0; a < 3; ++a) {
    const double t = s[a];
    B[a][2] = t * t * (3.0 - 2.0 * t);
    B[a][0] = 1.0 - B[a][2];
    B[a][1] = t * (1.0 - t) * (1.0 - t) * h[a];
    B[a][3] = -t * t * (1.0 - t) * h[a];
    dB[a][2] = 6.0 * t * (1.0 - t) / h[a];
    dB[a][0] = -dB[a][2];
    dB[a][1] = (1.0 - t) * (1.0 - 3.0 * t);
    dB[a][3] = t * (3.0 * t - 2.0);
  }
}

}  // namespace hapstate::playback
