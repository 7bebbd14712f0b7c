// What the playback benchmark measures on: the liver scene's playback file (built from
// pipelines/liver/scene.toml by the stage executables when missing, or HAPSTATE_PLAYBACK), a
// synthetic playback file over a >= 50 000-node box mesh, device paths and the liver Problem.
#pragma once

#include "problem/problem.h"

#include <hapstate/playback.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace hapstate::bench {

// The liver playback file: $HAPSTATE_PLAYBACK if set, else <build>/bench/liver_state/
// playback.bin, made by hapstate-import, -grid, -expand --max-seconds 60 --threads 2 and
// -index when it does not exist. Exits with a message if it cannot be had.
const PlaybackFile& liver_playback();

// A synthetic playback file written once per process to a temporary directory (removed at
// exit): a box mesh of 37^3 = 50 653 nodes (every node a view node), a 5 x 5 x 5 grid with
// one configuration per check-point, displacements from three smooth fields, linear forces.
const PlaybackFile& synthetic_playback();
// The same mesh on one cell (2 x 2 x 2 check-points) with every midpoint's data stored:
// deform() on half-spacing cells.
const PlaybackFile& synthetic_midpoint_playback();

// The liver scene's Problem for the precise solver.
const Problem& liver_problem();

// A device-like path for `file`: a seeded random walk from rest inside the grid box with
// `steps` steps of `step` mesh units, followed by the same walk backwards (so cycling through
// it never jumps).
std::vector<std::array<double, 3>> device_path(const PlaybackFile& file, int steps, double step,
                                               std::uint64_t seed);

}  // namespace hapstate::bench
