#include "statespace/batch_decision.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace hapstate {

BatchDecision decide_batch(const std::vector<TransitionTask>& tasks,
                           const std::vector<TransitionSolve>& solves, StoredLevels& stored,
                           const DecideSettings& settings) {
  BatchDecision out;
  BatchCounts& n = out.counts;
  ConfigId next_id = settings.next_id;
  for (std::size_t k = 0; k < tasks.size(); ++k) {
    const TransitionTask& task = tasks[k];
    const TransitionSolve& solve = solves[k];
    Transition t;
    t.source = task.source.id;
    t.direction = task.direction;
    ++out.decided[task.source.id];
    ++n.decided;
    if (!task.target) {
      t.outcome = TransitionOutcome::kOutsideGrid;
      ++n.outside;
      out.transitions.push_back(t);
      continue;
    }
    ++n.solved;
    if (solve.trivial) ++n.trivial;
    t.substeps = solve.move.substeps;
    t.newton_iterations = solve.move.iterations;
    // The start state's factorisation is shared by the source's directions, and which of them
    // pays it depends on the threads and batches: the catalogue keeps the transition's own.
    t.factorisations = solve.move.factorisations - solve.move.start_factorisations;
    n.factorisations += t.factorisations;
    t.final_residual = std::isfinite(solve.move.residual) ? solve.move.residual : 0.0;
    t.wall_ms = solve.move.wall_ms;
    if (!solve.move.ok) {
      t.outcome = TransitionOutcome::kFailed;
      t.failure_reason = std::string(failure_name(solve.move.failure)) + ": " + solve.move.reason;
      ++n.failed;
      out.transitions.push_back(t);
      continue;
    }
    t.outcome = TransitionOutcome::kReached;
    t.midpoint_force = solve.midpoint_force;
    t.midpoint_stiffness = solve.midpoint_stiffness;
    if (!solve.midpoint_u.empty()) {
      t.midpoint_blob = BlobRef{settings.segment, BlobRef::midpoint_group(task.source.id.value(),
                                                                          task.direction.index())};
    }
    // Compare with every level at the target, stored or new in this batch.
    const std::vector<double> summary = settings.sketch->summary(solve.vectors.u);
    // Sticking contact: levels with a different touched set are never equal, so the bound may
    // use this result's touched count; frictionless: h is the resultant force itself.
    const int probe_nodes = settings.bound_by_touched
                                ? std::max<int>(1, static_cast<int>(solve.vectors.touched.size()))
                                : settings.num_probe_nodes;
    double best = 2.0;
    ConfigId best_id;
    auto consider = [&](const Configuration& level, const ConfigVectors* in_memory) {
      if (level.status == ConfigStatus::kMerged) return;
      if (level_distance_bound(summary, solve.force, level.summary, level.force,
                               settings.tolerances, probe_nodes) > 1.0)
        return;
      const ConfigVectors& v = in_memory ? *in_memory : stored.vectors(level);
      const double d = level_distance(solve.vectors, v, settings.tolerances);
      if (d <= 1.0 && d < best) {
        best = d;
        best_id = level.id;
      }
    };
    for (const Configuration& level : stored.at(*task.target)) consider(level, nullptr);
    int new_here = 0;
    for (const NewConfiguration& fresh : out.fresh) {
      if (fresh.config.checkpoint != *task.target) continue;
      ++new_here;
      consider(fresh.config, fresh.vectors);
    }
    if (best_id.valid()) {
      t.target = best_id;
      ++n.reused_levels;
    } else {
      Configuration c;
      c.id = next_id;
      next_id = ConfigId(next_id.value() + 1);
      c.checkpoint = *task.target;
      c.level = Level(stored.next_level(*task.target).value() + new_here);
      c.wave = task.source.wave + 1;
      c.force = solve.force;
      c.expandable = settings.expandable(c.checkpoint, c.force);
      c.status = ConfigStatus::kOpen;
      c.blob = BlobRef{settings.segment, BlobRef::configuration_group(c.id.value())};
      c.summary = summary;
      t.target = c.id;
      out.fresh.push_back({c, &solve.vectors, out.transitions.size(), task.to});
      ++n.new_configurations;
    }
    out.transitions.push_back(t);
  }
  return out;
}

}  // namespace hapstate
