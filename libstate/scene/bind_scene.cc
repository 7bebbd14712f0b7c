#include "scene/bind.h"

#include "scene/diagnostics.h"
#include "scene/node_list.h"
#include "scene/rigid_modes.h"
#include "scene/select.h"
#include "solver/triangle_distance.h"

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
  }
  if (ids.empty() && diagnostics.count() == problems_before) {
    diagnostics.add(probe.line, "probe: " + what);
  }
  return ids;
}

// The contact sphere: candidates are the surface nodes with no fixed component (a partly fixed
// node cannot be held by the sticking sphere); the sphere at rest must not overlap the body.
ContactSphere bind_contact(const SceneProbe& probe, const Mesh& mesh,
                           const std::vector<DofRole>& role, Diagnostics& diagnostics) {
  ContactSphere sphere = make_contact_sphere(mesh, role, *probe.radius, probe.friction);
  if (sphere.candidates.empty()) {
    diagnostics.add(probe.line, "probe: contact: " + mesh_name(mesh) +
                                    " has no surface node without fixed components to touch");
  }
  for (int t = 0; t < mesh.surface.cols(); ++t) {
    const TrianglePoint tp =
        closest_point(mesh.nodes.col(mesh.surface(0, t)), mesh.nodes.col(mesh.surface(1, t)),
                      mesh.nodes.col(mesh.surface(2, t)), *probe.point);
    if (tp.distance < sphere.radius) {
      std::ostringstream os;
      os.precision(6);
      os << "probe: contact: the sphere at rest (centre " << format_point(*probe.point)
         << ", radius " << sphere.radius << ") overlaps the body: the surface point "
         << format_point(tp.closest) << " is at distance " << tp.distance
         << "; put probe.point at least probe.radius away from the body";
      diagnostics.add(probe.line, os.str());
      break;
    }
  }
  return sphere;
}

}  // namespace

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

  const SceneProbe& probe = scene.probe;
  if (probe.mode == ProbeMode::kContact) {
    problem.contact = bind_contact(probe, mesh, role, diagnostics);
    problem.probe_rest = *probe.point;
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

  for (const FreeRigidModes& f : free_rigid_modes(mesh, role)) {
    diagnostics.add(0, "the constraints leave " + std::to_string(f.free_modes) +
                           " rigid-body mode(s) free in component " + std::to_string(f.component) +
                           " of " + std::to_string(f.num_nodes) + " nodes (e.g. " + f.example +
                           "); add fixed nodes");
  }
  diagnostics.throw_if_any();

  problem.constraints.role = std::move(role);
  problem.mesh = std::move(mesh);
  return problem;
}

}  // namespace hapstate
