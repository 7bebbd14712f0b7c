// Deciding one solved batch of the expand stage (docs/state-space.md): what each transition
// records, which level of its target it reached, which results are new configurations. A pure
// function of the batch, of what is known about the stored levels and of the stage's
// settings: no catalogue, no file, no solver, no MPI. The stage then stores the decision
// (expand_stage.cc: stiffness of the new configurations, segment, one transaction).
#pragma once

#include "catalogue/records.h"
#include "statespace/expand_batch.h"
#include "statespace/level_match.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <map>
#include <vector>

namespace hapstate {

// What deciding needs to know about the configurations already stored.
class StoredLevels {
 public:
  virtual ~StoredLevels() = default;
  // The configurations at a check-point (merged ones are skipped by the caller).
  virtual std::vector<Configuration> at(CheckpointId checkpoint) = 0;
  // The level the next new configuration at the check-point gets.
  virtual Level next_level(CheckpointId checkpoint) = 0;
  // A stored configuration's vectors (asked only when its summary and force cannot rule it out).
  virtual const ConfigVectors& vectors(const Configuration& c) = 0;
};

struct DecideSettings {
  const LevelSketch* sketch = nullptr;
  LevelTolerances tolerances;
  // Sticking contact (touched sets stored): the summary bound uses the result's touched count;
  // otherwise num_probe_nodes.
  bool bound_by_touched = false;
  int num_probe_nodes = 1;
  // Whether a configuration at this check-point with this felt force is expanded further
  // (inside the workspace, |force| <= probe.max_force).
  std::function<bool(CheckpointId, const std::array<double, 3>&)> expandable;
  ConfigId next_id;   // the first new configuration's id
  SegmentId segment;  // the segment new vectors are written to
};

struct NewConfiguration {
  Configuration config;                    // blob in settings.segment, named "c<id>"
  const ConfigVectors* vectors = nullptr;  // points into the batch's solves
  std::size_t transition = 0;              // index in BatchDecision::transitions that reached it
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // its check-point, mesh units
};

struct BatchCounts {
  long long decided = 0, solved = 0, trivial = 0, failed = 0, factorisations = 0, outside = 0,
            new_configurations = 0, reused_levels = 0;
};

struct BatchDecision {
  std::vector<Transition> transitions;  // one per task, in task order
  std::vector<NewConfiguration> fresh;  // in task order, ids ascending from settings.next_id
  std::map<ConfigId, int> decided;      // transitions decided per source configuration
  BatchCounts counts;
};

// Tasks in canonical order; solves[k] belongs to tasks[k]. A result reaches the nearest level
// within the level tolerance among the stored ones and those this batch created before it;
// otherwise it is a new configuration (level = next stored level + new ones at that
// check-point so far, wave = source's + 1). Failed solves are recorded with their reason;
// tasks without a target as outside the grid.
BatchDecision decide_batch(const std::vector<TransitionTask>& tasks,
                           const std::vector<TransitionSolve>& solves, StoredLevels& stored,
                           const DecideSettings& settings);

}  // namespace hapstate
