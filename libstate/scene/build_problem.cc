// Kept apart from bind_scene.cc so that only users of build_problem link the mesh readers.
#include "scene/bind.h"

namespace hapstate {

Problem build_problem(const Scene& scene, MeshReport* report) {
  return bind_scene(scene, load_mesh(scene.mesh.file, report));
}

}  // namespace hapstate
