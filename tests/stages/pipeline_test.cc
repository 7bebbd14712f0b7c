// import -> grid -> expand on the beam: termination, the F_max bound, the zero configuration,
// skipping when nothing changed, thread-count independence, raising F_max and enlarging the
// workspace.
#include "beam_state.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "scene/grid_spec.h"
#include "statedir/stage_context.h"
#include "statedir/stored_problem.h"
#include "statespace/expand_batch.h"
#include "statespace/level_match.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <regex>

namespace hapstate::test_util {
namespace {

constexpr double kMaxForce = 0.01;    // pipelines/beam/scene.toml
constexpr int kBeamCheckpoints = 45;  // 5 x 3 x 3

double norm(const std::array<double, 3>& f) {
  return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
}

// One expanded beam (--threads 1) per test program, shared read-only by the tests.
class Pipeline : public StageTest {
 protected:
  static void SetUpTestSuite() {
    root_ = new fs::path(fs::temp_directory_path() /
                         ("hapstate_pipeline_test_" + std::to_string(::getpid())));
    fs::remove_all(*root_);
    fs::create_directories(*root_);
    build_beam(*root_ / "reference", kBeamScene, 1, *root_);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*root_);
    delete root_;
  }
  static fs::path reference() { return *root_ / "reference"; }
  fs::path copy_of_reference(const std::string& name) {
    const fs::path to = dir_ / name;
    fs::copy(reference(), to, fs::copy_options::recursive);
    return to;
  }

  static fs::path* root_;
};
fs::path* Pipeline::root_ = nullptr;

TEST_F(Pipeline, ExpansionTerminatesWithinTheForceLimit) {
  const Snapshot s = snapshot(reference());
  ASSERT_EQ(s.checkpoints.size(), static_cast<std::size_t>(kBeamCheckpoints));
  std::map<ConfigId, int> decided;
  for (const Transition& t : s.transitions) ++decided[t.source];
  int expandable = 0, beyond_limit = 0;
  for (const Configuration& c : s.configurations) {
    const bool within = norm(c.force) <= kMaxForce;
    EXPECT_EQ(c.expandable, within) << "configuration " << c.id.value();
    if (c.expandable) {
      ++expandable;
      EXPECT_EQ(decided[c.id], 26) << "configuration " << c.id.value();
      EXPECT_EQ(c.status, ConfigStatus::kExpanded);
    } else {
      ++beyond_limit;
      EXPECT_EQ(decided[c.id], 0) << "configuration " << c.id.value()
                                  << " beyond F_max was expanded";
      EXPECT_EQ(c.status, ConfigStatus::kOpen);
    }
  }
  // The beam is elastic and path-independent: one level per reached check-point. The axial
  // layers i = +-2 need more than F_max.
  EXPECT_EQ(s.configurations.size(), 45u);
  EXPECT_EQ(expandable, 27);
  EXPECT_EQ(beyond_limit, 18);
  for (const Configuration& c : s.configurations) EXPECT_EQ(c.level, Level(0));
  EXPECT_EQ(s.transitions.size(), 27u * 26u);
  int outside = 0, failed = 0;
  for (const Transition& t : s.transitions) {
    outside += t.outcome == TransitionOutcome::kOutsideGrid;
    failed += t.outcome == TransitionOutcome::kFailed;
  }
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(outside, 288);  // neighbours beyond the 5 x 3 x 3 box
}

// Every move that records a midpoint force stores the displacements and their slopes there
// too, and they agree with the stored states at both ends: u(mid) is near their mean, and the
// slope times the move is their central difference (second order: the beam bends little).
TEST_F(Pipeline, MidpointDisplacementsAgreeWithTheStatesAtBothEnds) {
  const Snapshot s = snapshot(reference());
  BlobStore blobs(reference() / "blobs");
  std::map<ConfigId, Configuration> by_id;
  for (const Configuration& c : s.configurations) by_id[c.id] = c;
  auto u_of = [&](ConfigId id) {
    const Configuration& c = by_id.at(id);
    return c.blob ? blobs.read(c.blob->segment, c.blob->name + "/u") : std::vector<double>{};
  };
  constexpr double kSpacing = 0.1;  // pipelines/beam/scene.toml
  int checked = 0;
  double worst_mean = 0, worst_difference = 0;
  for (const Transition& t : s.transitions) {
    if (t.outcome != TransitionOutcome::kReached) continue;
    ASSERT_EQ(t.midpoint_force.has_value(), t.midpoint_blob.has_value());
    if (!t.midpoint_blob) continue;
    const std::vector<float> mid =
        blobs.read_float32(t.midpoint_blob->segment, t.midpoint_blob->name + "/u");
    const std::vector<float> slope =
        blobs.read_float32(t.midpoint_blob->segment, t.midpoint_blob->name + "/du_dp");
    std::vector<double> from = u_of(t.source), to = u_of(t.target);
    const std::size_t n = mid.size();
    ASSERT_EQ(slope.size(), 3 * n);
    if (from.empty()) from.assign(n, 0.0);
    if (to.empty()) to.assign(n, 0.0);
    ASSERT_EQ(from.size(), n);
    ASSERT_EQ(to.size(), n);
    const auto o = t.direction.offset();
    double span = 0, mean = 0, difference = 0;
    for (std::size_t k = 0; k < n; ++k) {
      double predicted = 0;
      for (int a = 0; a < 3; ++a) predicted += slope[a * n + k] * o[a] * kSpacing;
      span = std::max(span, std::abs(to[k] - from[k]));
      mean = std::max(mean, std::abs(mid[k] - 0.5 * (from[k] + to[k])));
      difference = std::max(difference, std::abs(to[k] - from[k] - predicted));
    }
    worst_mean = std::max(worst_mean, mean / span);
    worst_difference = std::max(worst_difference, difference / span);
    ++checked;
  }
  std::printf(
      "[ info ] %d midpoints: |u(mid) - mean| <= %.3g, |difference - slope x move| <= %.3g "
      "of the largest change\n",
      checked, worst_mean, worst_difference);
  EXPECT_GT(checked, 100);
  EXPECT_LE(worst_mean, 0.05);
  EXPECT_LE(worst_difference, 0.01);
}

TEST_F(Pipeline, ZeroConfigurationAtTheRestCheckpoint) {
  Catalogue cat(reference() / "catalogue.sqlite", OpenMode::kReadOnly);
  const auto rest = cat.find_checkpoint({0, 0, 0});
  ASSERT_TRUE(rest);
  EXPECT_EQ(rest->position, (std::array<double, 3>{4.0, 0.5, 1.0}));
  EXPECT_EQ(rest->classification, CheckpointClass::kWorkspace);
  const auto at_rest = cat.configurations_at(rest->id);
  ASSERT_FALSE(at_rest.empty());
  const Configuration& zero = at_rest[0];
  EXPECT_EQ(zero.id, ConfigId(1));
  EXPECT_EQ(zero.level, Level(0));
  EXPECT_EQ(zero.wave, 0);
  EXPECT_EQ(zero.force, (std::array<double, 3>{0, 0, 0}));
  EXPECT_FALSE(zero.blob.has_value());
  EXPECT_TRUE(zero.expandable);
  // The rest stiffness is that of the beam's tip: positive on the diagonal, axial the stiffest.
  EXPECT_LT(zero.stiffness[0], 0.0);  // d(felt x)/dx: the user feels a restoring force
  EXPECT_LT(zero.stiffness[4], 0.0);
  EXPECT_LT(zero.stiffness[8], 0.0);
  EXPECT_GT(std::abs(zero.stiffness[0]), 10 * std::abs(zero.stiffness[4]));
  // Check-points: 5 x 3 x 3, indices relative to the rest position.
  for (const Checkpoint& c : cat.read_all_checkpoints()) {
    EXPECT_GE(c.ijk[0], -2);
    EXPECT_LE(c.ijk[0], 2);
    EXPECT_GE(c.ijk[1], -1);
    EXPECT_LE(c.ijk[1], 1);
    EXPECT_NEAR(c.position[0], 4.0 + 0.1 * c.ijk[0], 1e-12);
    EXPECT_NEAR(c.position[2], 1.0 + 0.1 * c.ijk[2], 1e-12);
  }
}

// The zero configurations' stiffness and slopes are computed once, by the import, and stored
// with the problem: the grid stage's zero configuration carries that stiffness, and a solve at
// rest gives the same numbers bit for bit. A directory imported before they were stored (no
// rest/stiffness) still gets them, computed.
TEST_F(Pipeline, TheRestStiffnessIsComputedOnceAtImport) {
  StageContext ctx = open_stage_context(reference(), StateAccess::kRead);
  const int nodes = ctx.problem.mesh.num_nodes();
  const std::optional<RestStiffness> stored = stored_rest_stiffness(ctx.dir, nodes);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->du_dp.size(), 9u * static_cast<std::size_t>(nodes));
  const RestStiffness solved = rest_stiffness(ctx.problem);
  EXPECT_EQ(stored->stiffness, solved.stiffness);
  EXPECT_EQ(stored->du_dp, solved.du_dp);
  const auto rest = ctx.catalogue.find_checkpoint({0, 0, 0});
  ASSERT_TRUE(rest);
  EXPECT_EQ(ctx.catalogue.configurations_at(rest->id).at(0).stiffness, stored->stiffness);

  const StateDir old{dir_ / "imported-before"};  // no problem segment: nothing stored
  fs::create_directories(old.root);
  EXPECT_FALSE(stored_rest_stiffness(old, nodes));
  const RestStiffness computed = zero_stiffness(old, ctx.problem);
  EXPECT_EQ(computed.stiffness, stored->stiffness);
  EXPECT_EQ(computed.du_dp, stored->du_dp);
}

TEST_F(Pipeline, RerunningUnchangedStagesDoesNothing) {
  const fs::path state = copy_of_reference("state");
  const auto before = snapshot(state);
  const StageResult i = import_stage(state, kBeamScene, dir_);
  EXPECT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("unchanged"), std::string::npos) << i.out;
  const StageResult g = grid_stage(state, dir_);
  EXPECT_EQ(g.exit_code, 0) << g.err;
  EXPECT_NE(g.out.find("unchanged"), std::string::npos) << g.out;
  const StageResult e = expand_stage(state, 1, dir_);
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.out.find("nothing to do"), std::string::npos) << e.out;
  const auto after = snapshot(state);
  expect_same_decisions(before, after);
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.read_stage_runs("import").back().outcome, StageOutcome::kUnchanged);
  EXPECT_EQ(cat.read_stage_runs("grid").back().outcome, StageOutcome::kUnchanged);
  EXPECT_EQ(cat.read_stage_runs("expand").back().outcome, StageOutcome::kUnchanged);
}

TEST_F(Pipeline, ThreadCountDoesNotChangeTheCatalogue) {
  const fs::path two = dir_ / "two";
  build_beam(two, kBeamScene, 2, dir_);
  const Snapshot a = snapshot(reference()), b = snapshot(two);
  expect_same_decisions(a, b);
  EXPECT_LE(max_vector_difference(reference(), two, a.configurations), 1e-12);
}

TEST_F(Pipeline, RaisingMaxForceExpandsFurtherAndRecomputesNothing) {
  const fs::path state = copy_of_reference("state");
  const Snapshot before = snapshot(state);
  std::vector<Transition> old_rows;
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    old_rows = cat.read_all_transitions();  // with wall times: a recomputed row would differ
  }
  const std::string scene =
      beam_variant(dir_, "stronger.toml", {{"max_force = 0.01", "max_force = 0.05"}});
  const StageResult i = import_stage(state, scene, dir_);
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("probe.max_force 0.01 N -> 0.05 N"), std::string::npos) << i.out;
  const StageResult g = grid_stage(state, dir_);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const StageResult e = expand_stage(state, 2, dir_);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.out.find("complete"), std::string::npos) << e.out;

  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  const auto now = cat.read_all_transitions();
  // Every old decision is still there, byte for byte (wall time included): nothing recomputed.
  std::map<std::pair<std::int64_t, int>, Transition> by_key;
  for (const Transition& t : now) by_key[{t.source.value(), t.direction.index()}] = t;
  for (const Transition& t : old_rows) {
    const auto it = by_key.find({t.source.value(), t.direction.index()});
    ASSERT_NE(it, by_key.end());
    EXPECT_EQ(it->second, t);
  }
  // The configurations that were beyond the old limit but within the new one were expanded.
  const auto configs = cat.read_all_configurations();
  int newly_expanded = 0;
  for (const Configuration& c : configs) {
    EXPECT_EQ(c.expandable, norm(c.force) <= 0.05);
    if (c.expandable) {
      EXPECT_EQ(c.status, ConfigStatus::kExpanded);
    }
  }
  for (const Configuration& c : before.configurations)
    if (!c.expandable && norm(c.force) <= 0.05) ++newly_expanded;
  EXPECT_EQ(newly_expanded, 18);
  EXPECT_EQ(now.size(), old_rows.size() + 18u * 26u);
  EXPECT_EQ(configs.size(), before.configurations.size());  // no new check-point reachable
}

TEST_F(Pipeline, EnlargedWorkspaceAddsCheckpointsAndKeepsTheOldOnes) {
  const fs::path state = copy_of_reference("state");
  const Snapshot before = snapshot(state);
  const std::string scene = beam_variant(
      dir_, "wider.toml",
      {{"box = [[3.8, 0.4, 0.9], [4.2, 0.6, 1.1]]", "box = [[3.8, 0.3, 0.9], [4.2, 0.7, 1.1]]"}});
  const StageResult i = import_stage(state, scene, dir_);
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("workspace enlarged"), std::string::npos) << i.out;
  // The grid must follow before the expansion continues.
  const StageResult early = expand_stage(state, 1, dir_);
  EXPECT_EQ(early.exit_code, 2) << early.err;
  EXPECT_NE(early.err.find("run hapstate-grid first"), std::string::npos) << early.err;
  const StageResult g = grid_stage(state, dir_);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_NE(g.out.find("30 check-points added (75 in all)"), std::string::npos) << g.out;
  const StageResult e = expand_stage(state, 2, dir_);
  ASSERT_EQ(e.exit_code, 0) << e.err;

  const Snapshot after = snapshot(state);
  ASSERT_EQ(after.checkpoints.size(), 75u);
  for (std::size_t k = 0; k < before.checkpoints.size(); ++k)
    EXPECT_EQ(after.checkpoints[k], before.checkpoints[k]);  // same ids, indices, positions
  for (std::size_t k = 0; k < before.configurations.size(); ++k) {
    EXPECT_EQ(after.configurations[k].force, before.configurations[k].force);
    EXPECT_EQ(after.configurations[k].blob, before.configurations[k].blob);
  }
  EXPECT_GT(after.configurations.size(), before.configurations.size());
  // Every expandable configuration is complete again.
  std::map<ConfigId, int> decided;
  for (const Transition& t : after.transitions) ++decided[t.source];
  for (const Configuration& c : after.configurations)
    if (c.expandable) {
      EXPECT_EQ(decided[c.id], 26) << c.id.value();
    }
}

// With level tolerances far below the solver's accuracy, arrivals by different paths are stored
// as distinct levels: many levels per check-point, decided in canonical order.
TEST_F(Pipeline, ManyLevelsAreDistinctAndIndependentOfThreads) {
  const std::string scene = beam_variant(
      dir_, "levels.toml",
      {{"[solver]",
        "[levels]\ndisplacement_tolerance = 1e-11\nforce_tolerance = 1e-9\n\n[solver]"}});
  const fs::path one = dir_ / "one", two = dir_ / "two";
  for (const auto& [state, threads] : {std::pair{one, 1}, std::pair{two, 2}}) {
    ASSERT_EQ(import_stage(state, scene, dir_).exit_code, 0);
    ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
    const StageResult e = expand_stage(state, threads, dir_, {"--max-transitions", "400"});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_NE(e.out.find("partial"), std::string::npos) << e.out;
  }
  const Snapshot a = snapshot(one), b = snapshot(two);
  expect_same_decisions(a, b);
  EXPECT_LE(max_vector_difference(one, two, a.configurations), 1e-12);
  EXPECT_EQ(a.transitions.size(), 402u);  // batches of 8 within waves: 26 + 376 at the limit

  // Levels at a check-point are 0..n-1 and pairwise farther apart than the tolerances.
  std::map<CheckpointId, std::vector<Configuration>> at;
  for (const Configuration& c : a.configurations) at[c.checkpoint].push_back(c);
  std::size_t most = 0;
  BlobStore blobs(one / "blobs");
  const LevelTolerances tol{1e-11, 1e-9};
  for (const auto& [checkpoint, levels] : at) {
    most = std::max(most, levels.size());
    std::vector<ConfigVectors> v;
    for (std::size_t l = 0; l < levels.size(); ++l) {
      EXPECT_EQ(levels[l].level, Level(static_cast<std::int64_t>(l)));
      v.push_back(load_config_vectors(blobs, levels[l], std::vector<double>(3 * 81, 0.0),
                                      VectorLayout{false, 3, 3}));
      // One grabbed node: the force felt is minus its reactions h; t is the probe offset.
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(levels[l].force[c], -v.back().h[c], 1e-12);
      const Checkpoint& p = a.checkpoints[checkpoint.value() - 1];
      const double rest[3] = {4.0, 0.5, 1.0};
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(v.back().t[c], p.position[c] - rest[c], 1e-12);
    }
    for (std::size_t x = 0; x < v.size(); ++x)
      for (std::size_t y = x + 1; y < v.size(); ++y)
        EXPECT_GT(level_distance(v[x], v[y], tol), 1.0)
            << checkpoint.value() << ": " << x << ", " << y;
  }
  EXPECT_GE(most, 5u);
}

}  // namespace
}  // namespace hapstate::test_util
