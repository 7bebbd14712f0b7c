// The check-point grid of a scene (docs/state-space.md): P_ijk = origin + (i, j, k) * spacing
// with origin = the probe's rest position, so the rest position is check-point (0, 0, 0) and
// indices may be negative. The check-points are those inside the workspace box (closed, with a
// tolerance of 1e-9 spacings); a box edge within 1e-3 spacings of the lattice is snapped to it
// (the workspace grows to include that check-point). Enlarging the workspace keeps every index and
// position.
#pragma once

#include "scene/scene.h"
#include "util/hash.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hapstate {

using GridIndex = std::array<int, 3>;

struct GridSpec {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   // probe rest position, mesh units
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();  // per axis, mesh units, > 0
  Box workspace;                                      // mesh units
  GridIndex lo{}, hi{};                               // inclusive index range per axis

  // The position of check-point ijk (the one formula every stage uses).
  Eigen::Vector3d position(const GridIndex& ijk) const;
  // Whether p lies in the workspace box (closed, tolerance 1e-9 spacings).
  bool in_workspace(const Eigen::Vector3d& p) const;
  // Whether ijk is within [lo, hi].
  bool contains(const GridIndex& ijk) const;
  std::int64_t num_checkpoints() const;
  // Hash of origin, spacing and workspace (what the grid stage depends on).
  ContentHash hash() const;
};

// Spacing per axis: grid.spacing, or box extent / (dims - 1).
Eigen::Vector3d grid_spacing(const SceneGrid& grid);

// The workspace: grid.box shifted by `sag` (how far the loaded rest state carried the grab point:
// the box is drawn around the mesh as drawn and follows it; Problem::probe_sag), or 4 spacings
// each way around `probe_rest`.
Box grid_workspace(const SceneGrid& grid, const Eigen::Vector3d& probe_rest,
                   const Eigen::Vector3d& sag = Eigen::Vector3d::Zero());

// Axes on which grid.dims asks for more check-points than grid.box holds (the probe's rest
// position is not on the box's lattice): one message per axis saying what was lost and how far
// to shift the box. Empty when grid.dims is not given.
std::vector<std::string> grid_short_axes(const SceneGrid& grid, const GridSpec& spec,
                                         const std::string& scene_label);

// Resolves the grid of a scene around the probe rest position (grid.box shifted by `sag`, as in
// grid_workspace). Throws InputError (naming `scene_label`) if the rest position lies outside
// the workspace.
GridSpec resolve_grid(const SceneGrid& grid, const Eigen::Vector3d& probe_rest,
                      const std::string& scene_label,
                      const Eigen::Vector3d& sag = Eigen::Vector3d::Zero());

}  // namespace hapstate
