// The grid stage (hapstate-grid): check-points, their classification and the zero
// configuration, from the imported scene.
#pragma once

#include "statedir/stage_run.h"

#include <cstdint>
#include <filesystem>
#include <string>

namespace hapstate {

struct GridOptions {
  std::filesystem::path state;

  // Throws InputError naming the first missing option (run_grid calls it first).
  void check() const;
};

struct GridReport : StageReport {
  std::int64_t checkpoints_added = 0;
  std::int64_t checkpoints_total = 0;
  bool zero_configuration_added = false;
  // Zero configurations added: at the rest check-point and (contact) at the free check-points.
  std::int64_t zero_configurations = 0;
  std::int64_t transitions_reopened = 0;  // kOutsideGrid decisions now inside the workspace
};

// Creates the check-points of the scene's grid (docs/state-space.md) that do not exist yet, in
// (i, j, k) order; the zero configuration at the rest check-point (0, 0, 0) if missing (u = 0,
// force 0, level 0, wave 0, no blob; the stiffness at rest the import stored); and, after the
// workspace was enlarged, deletes the kOutsideGrid transitions whose neighbour is now a
// workspace check-point and reopens their sources. Contact probe: a workspace check-point whose
// sphere touches no surface node of the rest shape is kFree and holds the zero configuration
// (no blob; the rest check-point is one of them); the others are kWorkspace, reached only by
// expansion. Existing check-points keep ids and indices.
// One transaction with an "grid" stage run. Skips ("unchanged") if the grid and the problem are
// those of the last grid run. Throws InputError (nothing changed) if the directory is not
// imported, or a stored check-point is not where the scene's grid puts it.
GridReport run_grid(const GridOptions& options);

}  // namespace hapstate
