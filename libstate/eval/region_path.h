// Random probe paths inside the precomputed region of a playback file: where a haptic cursor
// that follows the path finds every corner of its cell stored (reached through the stored
// transitions of the side it came from; none extended).
#pragma once

#include "hapstate/playback.h"
#include "io/probe_path.h"

#include <cstdint>

namespace hapstate {

// A seeded random walk of `steps` points from the rest position: each step moves
// `step_length` (mesh units) in a random direction chosen so that a cursor following the walk
// keeps every corner stored along the whole segment (tried 200 times, then the length is
// halved). Along an axis with a single check-point the walk stays on it. Deterministic for a
// seed on every platform. Throws InputError naming the file if the cell around the rest
// position is not stored (expand further).
ProbePath precomputed_random_path(const PlaybackFile& file, int steps, double step_length,
                                  std::uint64_t seed);

}  // namespace hapstate
