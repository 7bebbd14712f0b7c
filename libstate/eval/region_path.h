// Random probe paths inside the precomputed region of a playback file: where a haptic cursor
// that follows the path finds every corner of its cell stored and expanded (reached through
// the stored transitions of the side it came from; none extended, none on the open frontier of
// a partial expansion or past F_max).
#pragma once

#include "hapstate/playback.h"
#include "io/probe_path.h"

#include <cstdint>

namespace hapstate {

// A seeded random walk of `steps` points from the rest position: each step moves
// `step_length` (mesh units) in a random direction chosen so that a cursor following the walk
// keeps every corner stored and expanded along the whole segment (tried 200 times, then the length
// is halved). Along an axis with a single check-point the walk stays on it. With a contact probe
// each random direction is pulled toward the nearest surface node of the rest shape (the
// direction to it, weight `pull`, added before normalising), so the walk comes to touch the
// body instead of wandering in free space. Deterministic for a seed on every platform. Throws
// InputError naming the file if the cell around the rest position is not stored (expand
// further).
ProbePath precomputed_random_path(const PlaybackFile& file, int steps, double step_length,
                                  std::uint64_t seed, double pull = 0.7);

}  // namespace hapstate
