// Test problems for the contact probe: a block on a clamped base pressed from above, and the
// paper's thin plate clamped on its rim, touched from either side. Mesh units, unit = 0.01 m.
// `friction`: the sticking model unless a test asks for frictionless sliding.
#pragma once

#include "mesh/box_mesh.h"
#include "problem/problem.h"
#include "scene/select.h"

#include <algorithm>

namespace hapstate::testing {

// Candidates and roles as bind_scene makes them: surface nodes with no fixed component.
inline void add_contact_sphere(Problem* p, double radius, const Eigen::Vector3d& centre,
                               Friction friction) {
  ContactSphere sphere;
  sphere.radius = radius;
  sphere.friction = friction;
  for (int n : surface_nodes(p->mesh)) {
    bool fixed = false;
    for (int c = 0; c < 3; ++c) fixed = fixed || p->constraints.role[3 * n + c] != DofRole::kFree;
    if (!fixed) sphere.candidates.push_back(n);
  }
  p->contact = sphere;
  p->probe_rest = centre;
}

inline void fix_group(Problem* p, const std::string& group) {
  for (int n : p->mesh.groups.at(group))
    for (int c = 0; c < 3; ++c) p->constraints.role[3 * n + c] = DofRole::kFixed;
}

// Block [0, 4] x [0, 4] x [0, 1], base z = 0 clamped; sphere of radius 0.8 centred above the
// middle of the top face, 0.5 clear of it.
inline Problem block_problem(int cells = 8, Friction friction = Friction::kStick) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(4, 4, 1), cells, cells, 2);
  p.unit = 0.01;
  p.material = constants_from_young_poisson(Law::kNeoHooke, 5e3, 0.3);
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  fix_group(&p, "zmin");
  p.solver.substeps = 2;
  p.solver.tolerance = 1e-10;
  add_contact_sphere(&p, 0.8, Eigen::Vector3d(2, 2, 2.3), friction);
  return p;
}

// Plate [0, 4] x [0, 4] x [-0.1, 0.1], clamped on its four rim faces; the sphere of radius 0.5
// starts 1.0 below the plate's mid-plane centre.
inline Problem plate_problem(int cells = 10, Friction friction = Friction::kStick) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d(0, 0, -0.1), Eigen::Vector3d(4, 4, 0.2), cells, cells, 1);
  p.unit = 0.01;
  p.material = constants_from_young_poisson(Law::kNeoHooke, 5e4, 0.3);
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  for (const char* g : {"xmin", "xmax", "ymin", "ymax"}) fix_group(&p, g);
  p.solver.substeps = 4;
  p.solver.tolerance = 1e-10;
  add_contact_sphere(&p, 0.5, Eigen::Vector3d(2, 2, -1.0), friction);
  return p;
}

}  // namespace hapstate::testing
