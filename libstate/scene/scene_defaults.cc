// Defaults derived from several scene keys (docs/scene.md, [levels] and [grid]).
#include "scene/scene.h"

#include <algorithm>
#include <limits>

namespace hapstate {

namespace {
constexpr double kLevelRelativeTolerance = 1e-2;
}

double smallest_grid_spacing(const SceneGrid& grid) {
  if (grid.spacing) return grid.spacing->minCoeff();
  if (grid.dims && grid.box) {
    double h = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      h = std::min(h, (grid.box->max[k] - grid.box->min[k]) / ((*grid.dims)[k] - 1));
    }
    return h;
  }
  return 0.0;
}

LevelTolerances level_tolerances(const Scene& scene) {
  LevelTolerances t;
  t.displacement = scene.levels.displacement_tolerance.value_or(kLevelRelativeTolerance *
                                                                smallest_grid_spacing(scene.grid));
  t.force = scene.levels.force_tolerance.value_or(kLevelRelativeTolerance * scene.probe.max_force);
  return t;
}

}  // namespace hapstate
