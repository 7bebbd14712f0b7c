// decide_batch without a catalogue, files, solver or MPI: an in-memory set of stored levels and
// hand-made solve results. Checks the canonical order of new ids and levels, level matching
// against stored and same-batch configurations, the force limit, failures and the outside.
#include "statespace/batch_decision.h"

#include <gtest/gtest.h>

#include <map>

namespace hapstate {
namespace {

constexpr int kNodes = 4;

// Two free nodes, two fixed ones: the sketch samples nodes 0 and 1.
Problem four_node_problem() {
  Problem p;
  p.mesh.nodes = Eigen::Matrix3Xd::Zero(3, kNodes);
  p.constraints.role.assign(3 * kNodes, DofRole::kFree);
  for (int d = 6; d < 12; ++d) p.constraints.role[d] = DofRole::kFixed;
  return p;
}

class MemoryLevels final : public StoredLevels {
 public:
  std::vector<Configuration> at(CheckpointId c) override {
    std::vector<Configuration> out;
    for (const auto& [id, entry] : levels)
      if (entry.first.checkpoint == c) out.push_back(entry.first);
    ++lookups;
    return out;
  }
  Level next_level(CheckpointId c) override {
    int next = 0;
    for (const auto& [id, entry] : levels)
      if (entry.first.checkpoint == c)
        next = std::max<int>(next, static_cast<int>(entry.first.level.value()) + 1);
    return Level(next);
  }
  const ConfigVectors& vectors(const Configuration& c) override {
    ++vector_reads;
    return levels.at(c.id.value()).second;
  }
  std::map<std::int64_t, std::pair<Configuration, ConfigVectors>> levels;
  int lookups = 0, vector_reads = 0;
};

// u with node 0 displaced by x along x (everything else 0); h the reaction -force.
ConfigVectors vectors_with(double x, double force) {
  ConfigVectors v;
  v.u.assign(3 * kNodes, 0.0);
  v.u[0] = x;
  v.t = {x, 0, 0};
  v.h = {-force, 0, 0};
  return v;
}

TransitionTask task(std::int64_t source, int direction, std::optional<std::int64_t> target) {
  TransitionTask t;
  t.source.id = ConfigId(source);
  t.source.wave = 2;
  t.direction = Direction(direction);
  t.to = Eigen::Vector3d(direction, 0, 0);
  if (target) t.target = CheckpointId(*target);
  return t;
}

TransitionSolve reached(double x, double force) {
  TransitionSolve s;
  s.solved = true;
  s.move.ok = true;
  s.move.substeps = 1;
  s.move.iterations = 3;
  s.move.factorisations = 2;
  s.move.start_factorisations = 1;
  s.vectors = vectors_with(x, force);
  s.force = {force, 0, 0};
  return s;
}

class Decide : public ::testing::Test {
 protected:
  Decide() : problem_(four_node_problem()), sketch_(problem_) {
    settings_.sketch = &sketch_;
    settings_.tolerances = {0.01, 0.05};  // mesh units, N
    settings_.num_probe_nodes = 1;
    settings_.expandable = [](CheckpointId, const std::array<double, 3>& f) {
      return std::abs(f[0]) <= 1.0;  // F_max = 1 N
    };
    settings_.next_id = ConfigId(100);
    settings_.segment = SegmentId(7);
    // A stored level at check-point 5: node 0 at 0.5, force 0.4 N.
    Configuration c;
    c.id = ConfigId(10);
    c.checkpoint = CheckpointId(5);
    c.level = Level(0);
    c.force = {0.4, 0, 0};
    c.summary = sketch_.summary(vectors_with(0.5, 0.4).u);
    stored_.levels[10] = {c, vectors_with(0.5, 0.4)};
  }
  Problem problem_;
  LevelSketch sketch_;
  DecideSettings settings_;
  MemoryLevels stored_;
};

TEST_F(Decide, MatchesStoredAndSameBatchLevelsAndNumbersNewOnesInTaskOrder) {
  const std::vector<TransitionTask> tasks = {
      task(1, 0, 5),  // within tolerance of stored level 10
      task(1, 1, 5),  // far from it: new, level 1 at check-point 5
      task(2, 0, 5),  // within tolerance of the previous one (same batch): reuses it
      task(2, 1, 6),  // new at check-point 6, level 0
      task(2, 2, 5),  // far from both: new, level 2 at check-point 5
  };
  std::vector<TransitionSolve> solves = {reached(0.505, 0.41), reached(0.8, 0.6),
                                         reached(0.801, 0.6), reached(0.2, 0.1), reached(1.2, 0.9)};
  solves[3].midpoint_force = std::array<double, 3>{0.05, 0, 0};
  solves[3].midpoint_stiffness = std::array<double, 9>{-1, 0, 0, 0, -1, 0, 0, 0, -1};
  solves[3].midpoint_u = {0.01f, 0, 0};
  solves[3].midpoint_du_dp = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const BatchDecision d = decide_batch(tasks, solves, stored_, settings_);
  ASSERT_EQ(d.transitions.size(), 5u);
  EXPECT_EQ(d.transitions[0].target, ConfigId(10));
  EXPECT_EQ(d.transitions[1].target, ConfigId(100));
  EXPECT_EQ(d.transitions[2].target, ConfigId(100));
  EXPECT_EQ(d.transitions[3].target, ConfigId(101));
  EXPECT_EQ(d.transitions[4].target, ConfigId(102));
  // The force recorded half-way goes with its transition.
  EXPECT_EQ(d.transitions[3].midpoint_force, solves[3].midpoint_force);
  EXPECT_EQ(d.transitions[3].midpoint_stiffness, solves[3].midpoint_stiffness);
  EXPECT_FALSE(d.transitions[0].midpoint_force.has_value());
  // Its displacements go into the batch's segment, named after the transition.
  ASSERT_TRUE(d.transitions[3].midpoint_blob.has_value());
  EXPECT_EQ(d.transitions[3].midpoint_blob->segment, settings_.segment);
  EXPECT_EQ(d.transitions[3].midpoint_blob->name,
            "m" + std::to_string(tasks[3].source.id.value()) + "_1");
  EXPECT_FALSE(d.transitions[0].midpoint_blob.has_value());
  ASSERT_EQ(d.fresh.size(), 3u);
  EXPECT_EQ(d.fresh[0].config.level, Level(1));
  EXPECT_EQ(d.fresh[1].config.level, Level(0));
  EXPECT_EQ(d.fresh[1].config.checkpoint, CheckpointId(6));
  EXPECT_EQ(d.fresh[2].config.level, Level(2));
  for (const NewConfiguration& n : d.fresh) {
    EXPECT_EQ(n.config.wave, 3);
    EXPECT_EQ(n.config.status, ConfigStatus::kOpen);
    ASSERT_TRUE(n.config.blob);
    EXPECT_EQ(n.config.blob->segment, SegmentId(7));
    EXPECT_EQ(n.config.blob->name, "c" + std::to_string(n.config.id.value()));
    EXPECT_EQ(n.config.summary, sketch_.summary(n.vectors->u));
  }
  EXPECT_EQ(d.fresh[0].transition, 1u);
  EXPECT_EQ(d.fresh[0].vectors, &solves[1].vectors);
  EXPECT_EQ(d.fresh[2].position, Eigen::Vector3d(2, 0, 0));
  // The transition's own factorisations (the start state's are shared by its directions).
  EXPECT_EQ(d.transitions[0].factorisations, 1);
  EXPECT_EQ(d.counts.factorisations, 5);
  EXPECT_EQ(d.counts.new_configurations, 3);
  EXPECT_EQ(d.counts.reused_levels, 2);
  EXPECT_EQ(d.decided.at(ConfigId(1)), 2);
  EXPECT_EQ(d.decided.at(ConfigId(2)), 3);
  // Summaries rule out the far stored level without reading its vectors: only task 0 reads.
  EXPECT_EQ(stored_.vector_reads, 1);
}

TEST_F(Decide, NearestOfTwoLevelsWithinToleranceWins) {
  Configuration c = stored_.levels[10].first;
  c.id = ConfigId(11);
  c.level = Level(1);
  c.summary = sketch_.summary(vectors_with(0.51, 0.4).u);
  stored_.levels[11] = {c, vectors_with(0.51, 0.4)};
  const BatchDecision d = decide_batch({task(1, 0, 5)}, {reached(0.508, 0.4)}, stored_, settings_);
  EXPECT_EQ(d.transitions[0].target, ConfigId(11));
}

TEST_F(Decide, ForceLimitFailuresAndOutsideTheGrid) {
  TransitionSolve failed;
  failed.solved = true;
  failed.move.ok = false;
  failed.move.failure = SolveFailure::kLineSearch;
  failed.move.reason = "no descent";
  const std::vector<TransitionTask> tasks = {task(1, 0, 8), task(1, 1, 9),
                                             task(1, 2, std::nullopt)};
  const BatchDecision d =
      decide_batch(tasks, {reached(2.0, 1.5), failed, TransitionSolve{}}, stored_, settings_);
  ASSERT_EQ(d.fresh.size(), 1u);
  EXPECT_FALSE(d.fresh[0].config.expandable);  // 1.5 N > F_max
  EXPECT_EQ(d.transitions[1].outcome, TransitionOutcome::kFailed);
  EXPECT_FALSE(d.transitions[1].target.valid());
  EXPECT_EQ(d.transitions[1].failure_reason,
            std::string(failure_name(SolveFailure::kLineSearch)) + ": no descent");
  EXPECT_EQ(d.transitions[2].outcome, TransitionOutcome::kOutsideGrid);
  EXPECT_EQ(d.counts.decided, 3);
  EXPECT_EQ(d.counts.solved, 2);
  EXPECT_EQ(d.counts.failed, 1);
  EXPECT_EQ(d.counts.outside, 1);
  EXPECT_EQ(d.decided.at(ConfigId(1)), 3);
}

}  // namespace
}  // namespace hapstate
