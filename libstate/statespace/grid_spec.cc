#include "statespace/grid_spec.h"

#include "util/error.h"

#include <cmath>
#include <cstdio>

namespace hapstate {
namespace {

constexpr double kRelativeTolerance = 1e-9;  // of a spacing
constexpr double kDefaultWorkspaceSpacings = 4;

std::string point_text(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p.x(), p.y(), p.z());
  return buf;
}

}  // namespace

Eigen::Vector3d GridSpec::position(const GridIndex& ijk) const {
  return origin + Eigen::Vector3d(ijk[0] * spacing.x(), ijk[1] * spacing.y(), ijk[2] * spacing.z());
}

bool GridSpec::in_workspace(const Eigen::Vector3d& p) const {
  for (int a = 0; a < 3; ++a) {
    const double tol = kRelativeTolerance * spacing[a];
    if (p[a] < workspace.min[a] - tol || p[a] > workspace.max[a] + tol) return false;
  }
  return true;
}

bool GridSpec::contains(const GridIndex& ijk) const {
  for (int a = 0; a < 3; ++a)
    if (ijk[a] < lo[a] || ijk[a] > hi[a]) return false;
  return true;
}

std::int64_t GridSpec::num_checkpoints() const {
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= std::max(0, hi[a] - lo[a] + 1);
  return n;
}

ContentHash GridSpec::hash() const {
  ContentHasher h;
  h.update("grid-v1");
  for (int a = 0; a < 3; ++a) {
    h.update(origin[a]).update(spacing[a]).update(workspace.min[a]).update(workspace.max[a]);
  }
  return h.value();
}

Eigen::Vector3d grid_spacing(const SceneGrid& grid) {
  if (grid.spacing) return *grid.spacing;
  Eigen::Vector3d h;
  for (int a = 0; a < 3; ++a)
    h[a] = (grid.box->max[a] - grid.box->min[a]) / ((*grid.dims)[a] - 1);
  return h;
}

Box grid_workspace(const SceneGrid& grid, const Eigen::Vector3d& probe_rest) {
  if (grid.box) return *grid.box;
  const Eigen::Vector3d reach = kDefaultWorkspaceSpacings * grid_spacing(grid);
  return Box{probe_rest - reach, probe_rest + reach};
}

GridSpec resolve_grid(const SceneGrid& grid, const Eigen::Vector3d& probe_rest,
                      const std::string& scene_label) {
  GridSpec g;
  g.origin = probe_rest;
  g.spacing = grid_spacing(grid);
  g.workspace = grid_workspace(grid, probe_rest);
  if (!g.in_workspace(probe_rest)) {
    throw InputError(scene_label + ": [grid] box = [" + point_text(g.workspace.min) + ", " +
                     point_text(g.workspace.max) + "] does not contain the probe's rest position " +
                     point_text(probe_rest) + ": the workspace must contain it");
  }
  for (int a = 0; a < 3; ++a) {
    const double h = g.spacing[a];
    g.lo[a] = static_cast<int>(std::ceil((g.workspace.min[a] - probe_rest[a]) / h - kRelativeTolerance));
    g.hi[a] = static_cast<int>(std::floor((g.workspace.max[a] - probe_rest[a]) / h + kRelativeTolerance));
  }
  return g;
}

}  // namespace hapstate
