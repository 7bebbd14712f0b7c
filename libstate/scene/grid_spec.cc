#include "scene/grid_spec.h"

#include "util/error.h"

#include <cmath>
#include <cstdio>

namespace hapstate {
namespace {

constexpr double kRelativeTolerance = 1e-9;  // of a spacing
// A box edge this close to the lattice (in spacings) counts as on it: the check-point is kept
// and the workspace grows to it (a box written with rounded numbers).
constexpr double kSnapTolerance = 1e-3;
constexpr double kDefaultWorkspaceSpacings = 4;
// More check-points than this is a typo (a spacing in the wrong unit), not a workspace: each
// holds at least one equilibrium of the whole mesh.
constexpr double kMaxCheckpoints = 1e7;

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
  for (int a = 0; a < 3; ++a) h[a] = (grid.box->max[a] - grid.box->min[a]) / ((*grid.dims)[a] - 1);
  return h;
}

Box grid_workspace(const SceneGrid& grid, const Eigen::Vector3d& probe_rest,
                   const Eigen::Vector3d& sag) {
  if (grid.box && sag.isZero(0.0)) return *grid.box;  // bit for bit (a written -0.0 stays)
  if (grid.box) return Box{grid.box->min + sag, grid.box->max + sag};
  const Eigen::Vector3d reach = kDefaultWorkspaceSpacings * grid_spacing(grid);
  return Box{probe_rest - reach, probe_rest + reach};
}

GridSpec resolve_grid(const SceneGrid& grid, const Eigen::Vector3d& probe_rest,
                      const std::string& scene_label, const Eigen::Vector3d& sag) {
  GridSpec g;
  g.origin = probe_rest;
  g.spacing = grid_spacing(grid);
  g.workspace = grid_workspace(grid, probe_rest, sag);
  if (!g.in_workspace(probe_rest)) {
    throw InputError(scene_label + ": [grid] box = [" + point_text(g.workspace.min) + ", " +
                     point_text(g.workspace.max) + "] does not contain the probe's rest position " +
                     point_text(probe_rest) + ": the workspace must contain it");
  }
  double count = 1;
  for (int a = 0; a < 3; ++a)
    count *=
        std::floor((g.workspace.max[a] - g.workspace.min[a]) / g.spacing[a] + kSnapTolerance) + 1;
  if (!(count <= kMaxCheckpoints)) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  ": [grid] spacing (%.9g, %.9g, %.9g) over the box gives %.3g check-points; "
                  "hapstate takes at most %.0e (each holds an equilibrium of the whole mesh): a "
                  "larger grid.spacing (in mesh units) or a smaller grid.box",
                  g.spacing.x(), g.spacing.y(), g.spacing.z(), count, kMaxCheckpoints);
    throw InputError(scene_label + buf);
  }
  for (int a = 0; a < 3; ++a) {
    const double h = g.spacing[a];
    g.lo[a] =
        static_cast<int>(std::ceil((g.workspace.min[a] - probe_rest[a]) / h - kSnapTolerance));
    g.hi[a] =
        static_cast<int>(std::floor((g.workspace.max[a] - probe_rest[a]) / h + kSnapTolerance));
    // Widen only for a snapped check-point beyond the edge (not for a rounding ulp of one on
    // it: that would change the grid's hash for an unchanged scene).
    const double first = probe_rest[a] + g.lo[a] * h, last = probe_rest[a] + g.hi[a] * h;
    if (first < g.workspace.min[a] - kRelativeTolerance * h) g.workspace.min[a] = first;
    if (last > g.workspace.max[a] + kRelativeTolerance * h) g.workspace.max[a] = last;
  }
  return g;
}

std::vector<std::string> grid_short_axes(const SceneGrid& grid, const GridSpec& spec,
                                         const std::string& scene_label) {
  std::vector<std::string> notes;
  if (!grid.dims || !grid.box) return notes;
  for (int a = 0; a < 3; ++a) {
    const int have = spec.hi[a] - spec.lo[a] + 1, want = (*grid.dims)[a];
    if (have >= want) continue;
    const double h = spec.spacing[a], rest = spec.origin[a], edge = spec.workspace.min[a];
    const double shift = rest + std::round((edge - rest) / h) * h - edge;
    const char axis = "xyz"[a];
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: [grid] dims asks for %d check-points along %c but box holds %d: they lie "
                  "at the probe's rest position %c = %.9g plus multiples of the spacing %.9g, and "
                  "the box's %c edges are %.3g spacings off that lattice (more than the %g "
                  "snapped); shift grid.box by %.9g along %c, or give grid.spacing instead",
                  scene_label.c_str(), want, axis, have, axis, rest, h, axis, std::abs(shift) / h,
                  kSnapTolerance, shift, axis);
    notes.emplace_back(buf);
  }
  return notes;
}

}  // namespace hapstate
