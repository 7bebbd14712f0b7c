#include "scene/bind.h"

#include "mesh/winding_number.h"
#include "scene/diagnostics.h"
#include "scene/node_list.h"
#include "scene/rigid_modes.h"
#include "scene/select.h"
#include "solver/rest_state.h"
#include "solver/triangle_distance.h"
#include "util/error.h"

#include <algorithm>
#include <sstream>

namespace hapstate {
namespace {

constexpr int kMaxConflictsListed = 10;

std::string format_point(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(6);
  os << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
  return os.str();
}

std::string mesh_name(const Mesh& mesh) {
  return mesh.source.empty() ? std::string("the mesh") : "mesh " + mesh.source;
}

std::string describe(const FixedSelector& selector) {
  struct {
    std::string operator()(const BoxSelector& s) const {
      return "box [" + format_point(s.box.min) + ", " + format_point(s.box.max) + "]";
    }
    std::string operator()(const PlaneSelector& s) const {
      return "plane through " + format_point(s.point) + " normal " + format_point(s.normal);
    }
    std::string operator()(const GroupSelector& s) const { return "group '" + s.name + "'"; }
    std::string operator()(const NodesSelector& s) const { return "nodes file " + s.file.string(); }
  } visitor;
  return std::visit(visitor, selector.where);
}

// The nodes of physical group `name`; a missing group is reported (listing the known ones).
std::vector<int> group_nodes(const Mesh& mesh, const std::string& name, int line,
                             const std::string& label, Diagnostics& diagnostics) {
  const auto group = mesh.groups.find(name);
  if (group != mesh.groups.end()) return group->second;
  std::string known;
  for (const auto& [g, nodes] : mesh.groups) known += (known.empty() ? "" : ", ") + g;
  diagnostics.add(line, label + ": " + mesh_name(mesh) + " has no physical group '" + name + "' (" +
                            (known.empty() ? "it has none" : "groups: " + known) + ")");
  return {};
}

// Nodes selected by one [[fixed]] table; problems go to `diagnostics`.
std::vector<int> select_fixed(const FixedSelector& selector, const std::string& label,
                              const Mesh& mesh, Diagnostics& diagnostics) {
  const int problems_before = diagnostics.count();
  std::vector<int> ids;
  if (const auto* s = std::get_if<BoxSelector>(&selector.where)) {
    ids = nodes_in_box(mesh, s->box);
  } else if (const auto* s = std::get_if<PlaneSelector>(&selector.where)) {
    ids = nodes_on_plane(mesh, *s);
  } else if (const auto* s = std::get_if<GroupSelector>(&selector.where)) {
    ids = group_nodes(mesh, s->name, selector.line, label, diagnostics);
    if (ids.empty()) return {};
  } else if (const auto* s = std::get_if<NodesSelector>(&selector.where)) {
    ids = read_node_ids(s->file, mesh.num_nodes(), diagnostics);
  }
  if (ids.empty() && diagnostics.count() == problems_before) {
    diagnostics.add(selector.line,
                    label + " (" + describe(selector) + ") selects no node of " + mesh_name(mesh));
  }
  return ids;
}

// How far probe.point may be from the node it grabs (mesh units): 5 % of the mesh's bounding-box
// diagonal, or the longest edge of a tet at that node if longer (a coarse mesh).
double grab_snap_tolerance(const Mesh& mesh, int node) {
  const double diagonal =
      (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).norm();
  double edge = 0;
  for (int e = 0; e < mesh.num_tets(); ++e)
    for (int a = 0; a < 4; ++a)
      if (mesh.tets(a, e) == node)
        for (int b = 0; b < 4; ++b)
          edge = std::max(edge, (mesh.nodes.col(mesh.tets(b, e)) - mesh.nodes.col(node)).norm());
  return std::max(0.05 * diagonal, edge);
}

// The grabbed nodes of a grab probe; problems go to `diagnostics`.
std::vector<int> select_grabbed(const SceneProbe& probe, const Mesh& mesh,
                                Diagnostics& diagnostics) {
  const int problems_before = diagnostics.count();
  std::vector<int> ids;
  std::string what;
  if (probe.group) {
    ids = group_nodes(mesh, *probe.group, probe.line, "probe", diagnostics);
    what = "group '" + *probe.group + "' has no node";
  } else if (probe.nodes_file) {
    ids = read_node_ids(*probe.nodes_file, mesh.num_nodes(), diagnostics);
    what = "nodes file " + probe.nodes_file->string() + " lists no node";
  } else if (probe.point && probe.radius) {
    ids = surface_nodes_within(mesh, *probe.point, *probe.radius);
    std::ostringstream os;
    os << "no surface node of " << mesh_name(mesh) << " within radius " << *probe.radius << " of "
       << format_point(*probe.point);
    what = os.str();
  } else if (probe.point) {
    const int node = nearest_node(mesh, *probe.point);
    if (node >= 0) ids.push_back(node);
    what = mesh_name(mesh) + " has no node to grab";
    // A point far from the body is a mistake (a wrong unit or axis), not a wish to grab the
    // nearest node wherever it is: refuse it beyond grab_snap_tolerance.
    if (node >= 0) {
      const double distance = (mesh.nodes.col(node) - *probe.point).norm();
      const double tolerance = grab_snap_tolerance(mesh, node);
      if (distance > tolerance) {
        std::ostringstream os;
        os.precision(6);
        os << "probe: point " << format_point(*probe.point) << " is " << distance
           << " mesh units from the nearest node of " << mesh_name(mesh) << " (node " << node
           << " at " << format_point(mesh.nodes.col(node)) << "), more than the " << tolerance
           << " allowed (5 % of the mesh's bounding-box diagonal, or the longest edge at that "
              "node if longer): put probe.point on or near the body's surface";
        diagnostics.add(probe.line, os.str());
      }
    }
  }
  if (ids.empty() && diagnostics.count() == problems_before) {
    diagnostics.add(probe.line, "probe: " + what);
  }
  return ids;
}

// The contact sphere at rest must not overlap the body's surface, `positions` (mesh units).
void check_sphere_clear(const SceneProbe& probe, const Eigen::Matrix3Xd& positions,
                        const Triangles& surface, Diagnostics& diagnostics) {
  for (int t = 0; t < surface.cols(); ++t) {
    const TrianglePoint tp =
        closest_point(positions.col(surface(0, t)), positions.col(surface(1, t)),
                      positions.col(surface(2, t)), *probe.point);
    if (tp.distance < *probe.radius) {
      std::ostringstream os;
      os.precision(6);
      os << "probe: contact: the sphere at rest (centre " << format_point(*probe.point)
         << ", radius " << *probe.radius << ") overlaps the body: the surface point "
         << format_point(tp.closest) << " is at distance " << tp.distance
         << "; put probe.point at least probe.radius away from the body";
      diagnostics.add(probe.line, os.str());
      return;
    }
  }
  // Farther than the radius from every triangle, but possibly inside the body.
  if (WindingNumber(positions, surface)(*probe.point) > 0.5) {
    std::ostringstream os;
    os.precision(6);
    os << "probe: contact: the sphere at rest (centre " << format_point(*probe.point) << ", radius "
       << *probe.radius
       << ") is inside the body; put probe.point outside it, at least probe.radius away";
    diagnostics.add(probe.line, os.str());
  }
}

// The contact sphere: candidates are the surface nodes with no fixed component (a partly fixed
// node cannot be held by the sticking sphere).
ContactSphere bind_contact(const SceneProbe& probe, const Mesh& mesh,
                           const std::vector<DofRole>& role, Diagnostics& diagnostics) {
  ContactSphere sphere = make_contact_sphere(mesh, role, *probe.radius, probe.friction);
  if (sphere.candidates.empty()) {
    diagnostics.add(probe.line, "probe: contact: " + mesh_name(mesh) +
                                    " has no surface node without fixed components to touch");
  }
  return sphere;
}

// Solves the loaded rest state into problem->rest_m; a grab point follows its nodes there
// (probe_rest, probe_sag). (A contact probe with gravity is refused before.)
void settle_rest_state(const Scene& scene, Problem* problem) {
  const RestState rest = solve_rest_state(*problem);
  if (!rest.result.ok) {
    throw InputError(scene.path.string() + ":" + std::to_string(scene.loads.line) +
                     ": loads.gravity: the body's loaded rest state was not found (" +
                     rest.result.reason +
                     "); check material.density (kg/m^3), loads.gravity (m/s^2) and mesh.unit, "
                     "or hold the body with more [[fixed]] nodes or [[support]] surfaces");
  }
  problem->rest_m = rest.u_m;
  const std::vector<int>& grabbed = problem->constraints.probe_nodes;
  if (!grabbed.empty()) {
    Eigen::Vector3d sag = Eigen::Vector3d::Zero();
    for (int n : grabbed) sag += rest.u_m.segment<3>(3 * n);
    problem->probe_sag = sag / (static_cast<double>(grabbed.size()) * problem->unit);
    problem->probe_rest += problem->probe_sag;
  }
}

}  // namespace

std::string describe_grab(const Scene& scene, const Problem& problem) {
  std::ostringstream os;
  os.precision(3);
  const std::vector<int>& nodes = problem.constraints.probe_nodes;
  if (problem.contact) {
    os << "the probe is a sphere of radius " << problem.contact->radius;
  } else if (nodes.size() == 1 && scene.probe.point && !scene.probe.radius) {
    const Eigen::Vector3d drawn = problem.probe_rest - problem.probe_sag;
    os << "the probe grabs node " << nodes.front() << ", " << (drawn - *scene.probe.point).norm()
       << " mesh units from probe.point";
  } else {
    os << "the probe grabs " << nodes.size() << " node(s)";
  }
  return os.str();
}

ContactSphere make_contact_sphere(const Mesh& mesh, const std::vector<DofRole>& role, double radius,
                                  Friction friction) {
  ContactSphere sphere;
  sphere.radius = radius;
  sphere.friction = friction;
  for (int n : surface_nodes(mesh)) {
    bool fixed = false;
    for (int k = 0; k < 3; ++k)
      fixed = fixed || role[3 * static_cast<size_t>(n) + static_cast<size_t>(k)] != DofRole::kFree;
    if (!fixed) sphere.candidates.push_back(n);
  }
  return sphere;
}

Problem bind_scene(const Scene& scene, Mesh mesh) {
  Diagnostics diagnostics(scene.path.string());
  if (mesh.num_tets() == 0) {
    diagnostics.add(0, mesh_name(mesh) + " has no tetrahedra");
    diagnostics.throw_if_any();
  }
  Problem problem;
  problem.unit = scene.mesh.unit;
  problem.material = resolve_material(scene.material);
  problem.max_force = scene.probe.max_force;
  problem.solver = scene.solver;

  const auto dofs = 3 * static_cast<size_t>(mesh.num_nodes());
  std::vector<DofRole> role(dofs, DofRole::kFree);
  std::vector<int> fixed_by(dofs, -1);  // first [[fixed]] table fixing each DOF
  for (size_t i = 0; i < scene.fixed.size(); ++i) {
    const FixedSelector& selector = scene.fixed[i];
    for (int node : select_fixed(selector, "fixed[" + std::to_string(i) + "]", mesh, diagnostics)) {
      for (int k = 0; k < 3; ++k) {
        if (!selector.dofs[static_cast<size_t>(k)]) continue;
        const auto dof = 3 * static_cast<size_t>(node) + static_cast<size_t>(k);
        role[dof] = DofRole::kFixed;
        if (fixed_by[dof] < 0) fixed_by[dof] = static_cast<int>(i);
      }
    }
  }

  // Gravity and supports (fem/loads.h), in metres.
  const Eigen::Matrix3Xd positions_m = mesh.nodes * scene.mesh.unit;
  if (scene.loads.gravity && scene.material.density) {
    problem.loads.density = *scene.material.density;
    problem.loads.gravity = *scene.loads.gravity;
    problem.loads.force =
        gravity_force(positions_m, mesh.tets, *scene.material.density, *scene.loads.gravity);
  }
  for (size_t i = 0; i < scene.supports.size(); ++i) {
    const SupportSelector& support = scene.supports[i];
    const std::string label = "support[" + std::to_string(i) + "]";
    const std::vector<int> nodes = select_fixed(support.where, label, mesh, diagnostics);
    if (nodes.empty()) continue;
    std::vector<bool> selected(static_cast<size_t>(mesh.num_nodes()), false);
    for (int n : nodes) selected[static_cast<size_t>(n)] = true;
    if (add_surface_springs(positions_m, mesh.surface, selected, support.stiffness,
                            support.where.dofs, &problem.loads.spring) == 0) {
      diagnostics.add(support.where.line,
                      label + " (" + describe(support.where) + ") selects " +
                          std::to_string(nodes.size()) +
                          " node(s) but no surface triangle (one whose three corners are all "
                          "selected): a support acts on the surface");
    }
  }

  const bool has_probe = scene.has_probe;
  const SceneProbe& probe = scene.probe;
  if (!has_probe) {
    // hapstate-solve --rest: no probe; the body must be held by fixed nodes and supports.
  } else if (probe.mode == ProbeMode::kContact) {
    if (problem.loads.has_force()) {
      // The contact probe's playback (the cursor's free corners, the onset models) and its
      // solvers' "nothing touched" state still take the body at rest as the mesh as drawn.
      diagnostics.add(scene.loads.line,
                      "loads.gravity: not supported with a contact probe yet (its playback "
                      "takes the body at rest as the mesh as drawn): use a grab probe, or leave "
                      "gravity out ([[support]] alone is fine)");
    }
    problem.contact = bind_contact(probe, mesh, role, diagnostics);
    problem.probe_rest = *probe.point;
    check_sphere_clear(probe, mesh.nodes, mesh.surface, diagnostics);
  } else {
    const std::vector<int> grabbed = select_grabbed(probe, mesh, diagnostics);
    int conflicts = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int node : grabbed) {
      centroid += mesh.nodes.col(node);
      for (int k = 0; k < 3; ++k) {
        if (!probe.dofs[static_cast<size_t>(k)]) continue;
        const auto dof = 3 * static_cast<size_t>(node) + static_cast<size_t>(k);
        if (role[dof] != DofRole::kFixed) {
          role[dof] = DofRole::kProbe;
        } else if (++conflicts <= kMaxConflictsListed) {
          diagnostics.add(probe.line, "probe: node " + std::to_string(node) + " component " +
                                          "xyz"[k] + " is both fixed (by fixed[" +
                                          std::to_string(fixed_by[dof]) +
                                          "]) and grabbed by the probe");
        }
      }
    }
    if (conflicts > kMaxConflictsListed) {
      diagnostics.add(probe.line, "probe: ... and " +
                                      std::to_string(conflicts - kMaxConflictsListed) +
                                      " more DOF(s) both fixed and grabbed");
    }
    if (!grabbed.empty()) problem.probe_rest = centroid / static_cast<double>(grabbed.size());
    problem.constraints.probe_nodes = grabbed;
    problem.constraints.probe_components = probe.dofs;
  }
  diagnostics.throw_if_any();

  // A supported DOF holds the body as a fixed one does (for the rigid-body check only).
  std::vector<DofRole> held = role;
  for (size_t d = 0; d < held.size(); ++d)
    if (problem.loads.has_springs() && problem.loads.spring[static_cast<Eigen::Index>(d)] > 0 &&
        held[d] == DofRole::kFree)
      held[d] = DofRole::kFixed;
  for (const FreeRigidModes& f : free_rigid_modes(mesh, held)) {
    diagnostics.add(0, "the constraints leave " + std::to_string(f.free_modes) +
                           " rigid-body mode(s) free in component " + std::to_string(f.component) +
                           " of " + std::to_string(f.num_nodes) + " nodes (e.g. " + f.example +
                           "); add fixed nodes" + (scene.supports.empty() ? "" : " or supports"));
  }
  diagnostics.throw_if_any();
  if (problem.loads.has_force()) {
    // The body settles under its weight before the probe takes hold: fixed nodes and supports
    // alone must hold it.
    for (DofRole& r : held)
      if (r == DofRole::kProbe) r = DofRole::kFree;
    for (const FreeRigidModes& f : free_rigid_modes(mesh, held)) {
      diagnostics.add(scene.loads.line,
                      "loads.gravity: the fixed nodes and supports leave " +
                          std::to_string(f.free_modes) + " rigid-body mode(s) free in component " +
                          std::to_string(f.component) + " of " + std::to_string(f.num_nodes) +
                          " nodes (e.g. " + f.example +
                          "), so the body would fall before the probe takes hold of it; add "
                          "[[fixed]] nodes or [[support]] surfaces");
    }
    diagnostics.throw_if_any();
  }

  problem.constraints.role = std::move(role);
  problem.mesh = std::move(mesh);
  if (problem.loads.has_force()) settle_rest_state(scene, &problem);
  return problem;
}

}  // namespace hapstate
