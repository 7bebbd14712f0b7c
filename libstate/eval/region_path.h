// Random probe paths inside the precomputed region of a playback file: the cells whose 8
// corners all hold a stored configuration.
#pragma once

#include "hapstate/playback.h"
#include "io/probe_path.h"

#include <cstdint>

namespace hapstate {

// Whether the grid cell holding p (mesh units) has a stored configuration at all 8 corners.
bool in_precomputed_region(const PlaybackFile& file, const Eigen::Vector3d& p);

// A seeded random walk of `steps` points from the rest position: each step moves
// `step_length` (mesh units) in a random direction chosen so that the whole segment stays in
// the precomputed region (tried 200 times, then the length is halved). Deterministic for a
// seed on every platform. Throws InputError naming the file if the rest cell is not
// precomputed (expand further).
ProbePath precomputed_random_path(const PlaybackFile& file, int steps, double step_length,
                                  std::uint64_t seed);

}  // namespace hapstate
