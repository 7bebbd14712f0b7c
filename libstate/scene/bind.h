// Binding a validated Scene to its mesh: material constants, fixed and probe DOFs, the
// rigid-body check. The result is the Problem the solver consumes.
#pragma once

#include "mesh/load.h"
#include "mesh/mesh.h"
#include "problem/problem.h"
#include "scene/scene.h"

namespace hapstate {

// Material constants from the scene: young+poisson through constants_from_young_poisson, or
// the law's own constants. The others are filled with their small-strain equivalents
// (mu, lambda always; c10 = mu/2 and d1 = 2/K for linear/stvk).
MaterialConstants resolve_material(const SceneMaterial& material);

// Applies the scene to `mesh` (mesh units): fixed selectors -> kFixed, grabbed nodes -> kProbe
// on probe.dofs, probe_rest, then checks that fixed + probe DOFs remove all 6 rigid-body modes
// of every connected component. All problems (a selector selecting no node, a missing group,
// a bad node id, a DOF both fixed and grabbed, ...) are reported at once in one InputError;
// the rigid-body check runs only when there are no other problems. A contact probe gets
// Problem::contact (candidate nodes: surface nodes with no fixed component); its sphere at rest
// must not overlap the body's surface (its triangles), and the fixed DOFs alone must hold the body.
Problem bind_scene(const Scene& scene, Mesh mesh);

// The contact sphere of radius `radius` with `friction` on `mesh`: candidates (used by the
// sticking model) are the surface nodes none of whose DOFs is fixed (`role`), ascending.
ContactSphere make_contact_sphere(const Mesh& mesh, const std::vector<DofRole>& role, double radius,
                                  Friction friction);

// What a grab probe holds, for messages: "the probe grabs node N, D mesh units from
// probe.point" (probe.point alone: the nearest node; D as drawn) or "the probe grabs K node(s)";
// a contact probe: "the probe is a sphere of radius R".
std::string describe_grab(const Scene& scene, const Problem& problem);

// load_mesh(scene.mesh.file, report) then bind_scene.
Problem build_problem(const Scene& scene, MeshReport* report = nullptr);

}  // namespace hapstate
