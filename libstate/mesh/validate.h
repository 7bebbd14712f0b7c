// Shared validation of every reader's output: checks node references and coordinates, repairs
// orientation, drops degenerate and duplicate tets, reports unreferenced nodes, builds the
// outward boundary surface and the sorted node groups.
#pragma once

#include "mesh/load.h"
#include "mesh/mesh.h"
#include "mesh/raw_mesh.h"

namespace hapstate {

// A tet is degenerate when |det[b-a, c-a, d-a]| <= kDegenerateRelativeVolume * (longest edge)^3.
// A regular tet has det = l^3/sqrt(2) ~ 0.71 l^3; the worst bundled mesh (bunny) ~ 3e-3 l^3.
inline constexpr double kDegenerateRelativeVolume = 1e-9;

// Turns a reader's RawMesh into a valid Mesh (see the file comment). Throws InputError naming
// the file for non-finite coordinates, out-of-range node ids, no tets left, or a face shared by
// more than two tets. Fills `report` (may be null) with what was repaired.
Mesh validate_mesh(RawMesh raw, MeshReport* report);

}  // namespace hapstate
