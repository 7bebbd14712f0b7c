// Level comparison for compaction, on top of the state space's rule (statespace/level_match.h,
// docs/state-space.md): max(||u - u'||_inf / u_tol, ||h - h'||_2 / h_tol) <= 1 is one level.
// Adds what compaction meets and the expand stage does not: configurations without a blob
// and vectors of unequal lengths.
#pragma once

#include "catalogue/records.h"
#include "scene/scene.h"
#include "statespace/level_match.h"

#include <cstddef>

namespace hapstate {

// level_distance of two configurations' vectors; an empty u or h (no blob) counts as zeros of
// the other's length; different non-zero lengths are never the same level (+infinity).
double compaction_level_distance(const ConfigVectors& a, const ConfigVectors& b,
                                 const LevelTolerances& tolerances);

// The cheap lower bound of the distance from catalogue rows only (summaries of u and forces,
// level_distance_bound); `h_length` = the larger number of reaction values of the two (an
// upper bound of the probe nodes, as each node has at least one probe DOF). > 1 proves two
// different levels without reading a blob.
double compaction_distance_bound(const Configuration& a, const Configuration& b,
                                 std::size_t h_length, const LevelTolerances& tolerances);

}  // namespace hapstate
