// The imported mesh and constraints, kept in the state directory (problem/seg-000001.h5) so
// that later stages and playback never need the original mesh or node files again.
// Vectors (zstd): float64 mesh/nodes (3 per node, mesh units) and probe/rest (3, mesh units);
// int32 mesh/tets (4 per tet), mesh/surface (3 per triangle), constraints/role (one DofRole per
// DOF), constraints/probe_nodes and constraints/probe_components (3 flags);
// with gravity or supports (fem/loads.h) also loads/force (N per DOF), loads/spring (N/m per
// DOF), rest/u (the loaded rest state, metres per DOF) and probe/sag (3, mesh units), each only
// where it is not empty (a scene without loads stores and hashes what it always did); and the
// zero configurations' haptic stiffness rest/stiffness (9, row-major, N per mesh unit) and
// displacement slopes rest/du_dp (float32, d u / d p: 3 columns of one value per DOF), computed
// once by the import (a state directory imported before they were stored has neither).
#pragma once

#include "blobs/segment.h"
#include "problem/problem.h"
#include "scene/scene.h"
#include "statedir/state_dir.h"
#include "util/hash.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace hapstate {

// The stored problem's vectors, in memory as float64 (the int32 datasets widened on reading).
struct ProblemVectors {
  std::vector<double> nodes, tets, surface, role, probe_nodes, probe_components, rest;
  std::vector<double> force, spring, rest_u, sag;  // empty without loads
};

inline constexpr SegmentId kProblemSegment{1};

// Hash of the stored problem's inputs (geometry, constraints, probe rest as drawn... and the
// loads' force and springs): equal hashes mean the same problem. The loaded rest state (rest/u)
// and the sag it gives the grab point (probe/sag) are stored with it but not hashed: they are
// the solver's answer to those inputs.
ContentHash problem_hash(const Problem& problem);

// The zero configurations' haptic stiffness and displacement slopes: the body at rest, the probe
// at rest (they store no blob of their own). Like rest/u, not hashed: the solver's answer.
struct RestStiffness {
  std::array<double, 9> stiffness{};  // row-major, N per mesh unit
  std::vector<float> du_dp;           // 3 columns of one value per DOF (empty: none)
};

// Writes the problem segment, with the rest state's stiffness, into dir.problem() (which must
// not hold one yet), closed and fsynced when this returns.
void write_stored_problem(const StateDir& dir, const Problem& problem,
                          const ContentHash& scene_hash, const RestStiffness& rest);

// The rest state's stiffness as the import stored it; nullopt for a state directory imported
// before it was stored (the caller then computes it). Throws InputError naming the segment if
// it is stored with the wrong size.
std::optional<RestStiffness> stored_rest_stiffness(const StateDir& dir, int num_nodes);

// Rebuilds the Problem from the stored segment and the scene's material, unit, solver options
// and max_force. Throws InputError naming the segment if it is missing or unreadable, or if
// its hash differs from `expected` (the import stage's record).
Problem load_stored_problem(const StateDir& dir, const Scene& scene, const ContentHash& expected);

// The zero configuration's u (mesh units, 3 per node) as stored: the loaded rest state
// ("rest/u" / `unit`, the scene's mesh.unit), or empty for a problem without a body force (u = 0).
std::vector<double> stored_rest_displacements(const StateDir& dir, double unit);

// The vectors load_stored_problem reads, taken from a Problem (what the expand stage's
// coordinator sends to worker ranks that cannot read the state directory).
ProblemVectors problem_vectors(const Problem& problem);
// The Problem those vectors and the scene make; the same checks as load_stored_problem, with
// `where` naming the source in messages.
Problem problem_from_vectors(const ProblemVectors& v, const Scene& scene,
                             const ContentHash& expected, const std::string& where);

}  // namespace hapstate
