// What a state directory depends on, as named content hashes (recorded as the import stage's
// inputs). Parts that may change in an existing state directory: "scene" (the text, e.g.
// comments), "max_force" and "workspace" (enlarging only). Any other part changing invalidates
// every configuration: the import refuses it unless asked for a fresh state directory.
#pragma once

#include "problem/problem.h"
#include "scene/scene.h"
#include "util/hash.h"

#include <string>
#include <utility>
#include <vector>

namespace hapstate {

using NamedHashes = std::vector<std::pair<std::string, ContentHash>>;  // sorted by name

// Parts: "grid.spacing", "levels", "material", "max_force", "mesh" (= mesh_hash, the mesh
// file's bytes), "probe", "problem" (stored mesh + constraints), "scene" (text), "solver",
// "workspace".
NamedHashes scene_identity(const Scene& scene, const Problem& problem,
                           const ContentHash& mesh_hash);

// Whether a changed part may change in an existing state directory.
bool is_mutable_scene_part(const std::string& part);

// What a part is, for messages ("the material ([material] and mesh.unit)").
std::string describe_scene_part(const std::string& part);

}  // namespace hapstate
