// A small synthetic state directory written through the Catalogue and SegmentWriter API (no
// expand stage): 4 check-points, 8 configurations over 3 blob segments, 10 transitions, 3
// stage runs. Its duplicates are known exactly (see synthetic_state.cc):
//   c4 duplicates c3 (distance 0.5), c8 duplicates c6 (0.99); c5 is 1.05 tolerances from c3
//   (u), c7 1.01 from c6 (h): both just outside. Tolerances: u 0.01, h 0.05 (scene [levels]).
#pragma once

#include "catalogue/records.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate::test_util {

inline constexpr double kUTol = 0.01;
inline constexpr double kHTol = 0.05;
inline constexpr int kLiverNodes = 181;

// The bundled liver mesh the displacement vectors refer to.
std::filesystem::path liver_mesh();

// Writes the state into `dir` (created; must not hold a state yet).
void write_synthetic_state(const std::filesystem::path& dir);

// u of configuration `id` as written (empty for c1, the zero state).
std::vector<double> synthetic_u(int id);

}  // namespace hapstate::test_util
