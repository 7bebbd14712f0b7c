// The imported mesh and constraints, kept in the state directory (problem/seg-000001.h5) so
// that later stages and playback never need the original mesh or node files again.
// Vectors (float64, zstd): mesh/nodes (3 per node, mesh units), mesh/tets (4 per tet),
// mesh/surface (3 per triangle), constraints/role (one DofRole per DOF),
// constraints/probe_nodes, constraints/probe_components (3 flags), probe/rest (3, mesh units).
#pragma once

#include "blobs/segment.h"
#include "util/hash.h"
#include "scene/problem.h"
#include "scene/scene.h"
#include "statespace/state_dir.h"

namespace hapstate {

inline constexpr SegmentId kProblemSegment{1};

// Hash of everything the stored problem holds (geometry, constraints, probe rest): equal
// hashes mean the same stored vectors.
ContentHash problem_hash(const Problem& problem);

// Writes the problem segment into dir.problem() (which must not hold one yet), closed and
// fsynced when this returns.
void write_stored_problem(const StateDir& dir, const Problem& problem,
                          const ContentHash& scene_hash);

// Rebuilds the Problem from the stored segment and the scene's material, unit, solver options
// and max_force. Throws InputError naming the segment if it is missing or unreadable, or if
// its hash differs from `expected` (the import stage's record).
Problem load_stored_problem(const StateDir& dir, const Scene& scene, const ContentHash& expected);

}  // namespace hapstate
