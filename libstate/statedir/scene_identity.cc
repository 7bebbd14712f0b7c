#include "statedir/scene_identity.h"

#include "scene/grid_spec.h"
#include "statedir/stored_problem.h"

#include <algorithm>

namespace hapstate {
namespace {

void update_optional(ContentHasher& h, const std::optional<double>& v) {
  if (v) {
    h.update(std::int64_t{1}).update(*v);
  } else {
    h.update(std::int64_t{0});
  }
}

}  // namespace

NamedHashes scene_identity(const Scene& scene, const Problem& problem,
                           const ContentHash& mesh_hash) {
  NamedHashes parts;
  parts.emplace_back("scene", content_hash(scene.text));
  parts.emplace_back("mesh", mesh_hash);
  parts.emplace_back("problem", problem_hash(problem));
  {
    const MaterialConstants& m = problem.material;
    ContentHasher h;
    h.update(static_cast<std::int64_t>(m.law)).update(m.mu).update(m.lambda).update(m.c10);
    h.update(m.c01).update(m.d1).update(problem.unit);
    parts.emplace_back("material", h.value());
  }
  {
    ContentHasher h;
    h.update(static_cast<std::int64_t>(scene.probe.mode));
    // Contact: the sphere radius decides every configuration (grab hashes stay as they were).
    if (problem.contact) h.update(problem.contact->radius);
    // Sliding contact is a different model: its states differ from sticking ones.
    if (problem.contact && problem.contact->friction == Friction::kNone)
      h.update(std::string_view("frictionless"));
    parts.emplace_back("probe", h.value());
  }
  {
    const SolverOptions& s = scene.solver;
    ContentHasher h;
    h.update(static_cast<std::int64_t>(s.substeps))
        .update(s.tolerance)
        .update(s.absolute_tolerance);
    h.update(static_cast<std::int64_t>(s.max_iterations))
        .update(static_cast<std::int64_t>(s.max_cutbacks));
    parts.emplace_back("solver", h.value());
  }
  {
    ContentHasher h;
    update_optional(h, scene.levels.displacement_tolerance);
    update_optional(h, scene.levels.force_tolerance);
    parts.emplace_back("levels", h.value());
  }
  {
    const Eigen::Vector3d spacing = grid_spacing(scene.grid);
    ContentHasher h;
    h.update(std::span<const double>(spacing.data(), 3));
    parts.emplace_back("grid.spacing", h.value());
  }
  {
    ContentHasher h;
    h.update(scene.probe.max_force);
    parts.emplace_back("max_force", h.value());
  }
  {
    // As drawn: the sag is the solver's answer, not part of the scene.
    const Box w = grid_workspace(scene.grid, problem.probe_rest - problem.probe_sag);
    ContentHasher h;
    h.update(std::span<const double>(w.min.data(), 3))
        .update(std::span<const double>(w.max.data(), 3));
    parts.emplace_back("workspace", h.value());
  }
  std::sort(parts.begin(), parts.end());
  return parts;
}

bool is_mutable_scene_part(const std::string& part) {
  return part == "scene" || part == "max_force" || part == "workspace";
}

std::string describe_scene_part(const std::string& part) {
  if (part == "mesh") return "the mesh file's content";
  if (part == "problem")
    return "the mesh geometry, the fixed/grabbed nodes or the loads ([[fixed]], [probe], [loads], "
           "[[support]], material.density)";
  if (part == "material") return "the material ([material] or mesh.unit)";
  if (part == "probe")
    return "the probe mode (probe.mode), the contact sphere's radius or its friction";
  if (part == "solver") return "the solver options ([solver])";
  if (part == "levels") return "the level tolerances ([levels])";
  if (part == "grid.spacing") return "the grid spacing (grid.spacing or grid.dims with grid.box)";
  if (part == "max_force") return "probe.max_force";
  if (part == "workspace") return "the workspace (grid.box)";
  return "the scene text";
}

}  // namespace hapstate
