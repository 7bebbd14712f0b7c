// The state space of a contact probe, through the real stages on the bundled plate scene
// (pipelines/plate/): free check-points hold the shared zero configuration, moves between them
// need no solve, the check-points in the plate's swept region hold a level pushed from below
// and one pushed from above with opposite normal forces, and leaving the plate gives the zero
// configuration back.
#include "beam_state.h"
#include "statespace/expand_batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace hapstate::test_util {
namespace {

class ContactState : public ::testing::Test {
 protected:
  void SetUp() override {
    // A parameterised test's name holds a '/' ("Name/0"): one folder level, not two, so that
    // TearDown removes all of it.
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');
    dir_ = fs::temp_directory_path() /
           ("hapstate_contact_state_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  // import, grid, expand (extra expand arguments) of `scene` into dir_/state.
  void run_all(const std::string& scene, std::vector<std::string> expand_extra = {}) {
    const StageResult i = import_stage(state(), scene, dir_);
    ASSERT_EQ(i.exit_code, 0) << i.err;
    const StageResult g = grid_stage(state(), dir_);
    ASSERT_EQ(g.exit_code, 0) << g.err;
    const StageResult e = expand_stage(state(), 1, dir_, std::move(expand_extra));
    ASSERT_TRUE(e.exit_code == 0) << e.err;
  }
  fs::path state() const { return dir_ / "state"; }
  fs::path dir_;
};

Eigen::Vector3d force_of(const Configuration& c) {
  return Eigen::Vector3d(c.force[0], c.force[1], c.force[2]);
}

// The column through the plate's middle, frictionless (the default).
constexpr const char* kBundledBox = "box = [[1.8, 1.8, -1.0], [2.2, 2.2, 1.0]]";
constexpr const char* kColumnBox = "box = [[1.9, 1.9, -1.0], [2.1, 2.1, 1.0]]";

TEST_F(ContactState, PlateColumnHoldsBothSidesAndLeavingGivesTheZeroConfiguration) {
  run_all(plate_variant(dir_, {{kBundledBox, kColumnBox}}));
  Catalogue cat(state() / "catalogue.sqlite", OpenMode::kReadOnly);
  BlobStore blobs(state() / "blobs");
  std::map<int, Checkpoint> by_k;  // the column: i = j = 0, k = 0 .. 10 (z = -1.0 .. 1.0)
  for (const Checkpoint& c : cat.read_all_checkpoints())
    if (c.ijk[0] == 0 && c.ijk[1] == 0) by_k.emplace(c.ijk[2], c);
  ASSERT_EQ(by_k.size(), 11u);
  for (int k = 0; k <= 10; ++k) {
    const std::vector<Configuration> levels = cat.configurations_at(by_k.at(k).id);
    const double z = -1.0 + 0.2 * k;
    SCOPED_TRACE("z = " + std::to_string(z));
    // Free (the sphere of radius 0.8 clear of the plate, |z| >= 0.9): only the shared zero
    // configuration, no blob, exactly zero force.
    if (std::abs(z) > 0.9) {
      EXPECT_EQ(by_k.at(k).classification, CheckpointClass::kFree);
      ASSERT_EQ(levels.size(), 1u);
      EXPECT_FALSE(levels[0].blob.has_value());
      EXPECT_EQ(force_of(levels[0]), Eigen::Vector3d::Zero());
      continue;
    }
    EXPECT_EQ(by_k.at(k).classification, CheckpointClass::kWorkspace);
    ASSERT_GE(levels.size(), 1u);
    for (const Configuration& c : levels) {
      ASSERT_TRUE(c.blob.has_value());
      // Frictionless: h is the sphere's force on the body, minus the felt force; no t.
      const ConfigVectors v = load_config_vectors(blobs, c, std::vector<double>(3 * 242, 0.0),
                                                  VectorLayout{false, 0, 3});
      EXPECT_TRUE(v.t.empty());
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(v.h[k], -c.force[k], 1e-12);
    }
    // The swept region: the sphere centre within 0.2 of the mid-plane is reached from below
    // (plate bent up, force down) and from above (bent down, force up) within max_force.
    if (std::abs(z) < 0.25) {
      ASSERT_GE(levels.size(), 2u);
      const Configuration* down = nullptr;
      const Configuration* up = nullptr;
      for (const Configuration& c : levels) {
        if (c.force[2] < 0 && (!down || c.force[2] < down->force[2])) down = &c;
        if (c.force[2] > 0 && (!up || c.force[2] > up->force[2])) up = &c;
      }
      ASSERT_TRUE(down && up);
      for (const Configuration* c : {down, up}) {
        const Eigen::Vector3d f = force_of(*c);
        EXPECT_GT(std::abs(f.z()), 0.1);
        EXPECT_LT(f.head<2>().norm(), 0.02 * std::abs(f.z()));  // frictionless: ~normal
      }
      EXPECT_LT(force_of(*down).normalized().dot(force_of(*up).normalized()), -0.97);
    }
  }
  // Leaving: from the first touching check-point on either side, the move out to the free
  // check-point reaches its zero configuration.
  const Configuration zero_below = cat.configurations_at(by_k.at(0).id)[0];
  const Configuration zero_above = cat.configurations_at(by_k.at(10).id)[0];
  int left = 0;
  for (const Transition& t : cat.read_all_transitions()) {
    if (t.outcome != TransitionOutcome::kReached) continue;
    const Configuration source = cat.read_configuration(t.source);
    const auto off = t.direction.offset();
    if (off[0] != 0 || off[1] != 0) continue;
    if (source.checkpoint == by_k.at(1).id && off[2] == -1) {
      EXPECT_EQ(t.target, zero_below.id);
      ++left;
    }
    if (source.checkpoint == by_k.at(9).id && off[2] == 1) {
      EXPECT_EQ(t.target, zero_above.id);
      ++left;
    }
  }
  EXPECT_EQ(left, 2);
}

// A 3-D workspace over the plate, frictionless: the expansion completes, and no check-point
// holds more than the two genuine levels (pushed from below, from above); sliding does not
// multiply them as sticking did (~680 levels at one check-point on a 3 x 3 x 11 grid).
TEST_F(ContactState, ThreeDimensionalWorkspaceHasAtMostTwoLevelsPerCheckpoint) {
  run_all(plate_variant(dir_, {{kBundledBox, "box = [[1.6, 1.6, -1.2], [2.4, 2.4, 1.2]]"},
                               {"spacing = 0.2", "spacing = 0.4"}}));
  Catalogue cat(state() / "catalogue.sqlite", OpenMode::kReadOnly);
  std::map<CheckpointId, int> levels;
  for (const Configuration& c : cat.read_all_configurations())
    if (c.status != ConfigStatus::kMerged) ++levels[c.checkpoint];
  std::map<int, int> histogram;
  for (const auto& [checkpoint, count] : levels) ++histogram[count];
  for (const auto& [count, checkpoints] : histogram)
    std::printf("%d level(s): %d check-points\n", count, checkpoints);
  ASSERT_FALSE(histogram.empty());
  EXPECT_LE(histogram.rbegin()->first, 2);
  EXPECT_GT(histogram[2], 0);  // the plate's swept region: both sides
  int open = 0, failed = 0;
  for (const Configuration& c : cat.read_all_configurations())
    open += c.status == ConfigStatus::kOpen && force_of(c).norm() <= 0.5 ? 1 : 0;
  for (const Transition& t : cat.read_all_transitions())
    failed += t.outcome == TransitionOutcome::kFailed ? 1 : 0;
  EXPECT_EQ(open, 0);  // complete: every expandable configuration expanded
  EXPECT_EQ(failed, 0);
}

// A workspace where the sphere never reaches the body is bad input naming grid.box; nothing is
// added to the state directory.
TEST_F(ContactState, WorkspaceThatNeverTouchesIsRefused) {
  const std::string scene =
      plate_variant(dir_, {{kBundledBox, "box = [[1.8, 1.8, -1.4], [2.2, 2.2, -1.0]]"}});
  ASSERT_EQ(import_stage(state(), scene, dir_).exit_code, 0);
  const StageResult g = grid_stage(state(), dir_);
  EXPECT_EQ(g.exit_code, 2) << g.err;
  EXPECT_NE(g.err.find("grid.box: the sphere (probe.radius 0.8"), std::string::npos) << g.err;
  EXPECT_NE(g.err.find("could never touch it"), std::string::npos) << g.err;
  Catalogue cat(state() / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_TRUE(cat.read_all_configurations().empty());  // the grid transaction rolled back
}

// Free check-points side by side (the layer z = -1.0 of a 3 x 3 grid): their zero
// configurations are joined without a solve; moves into the plate are solved.
TEST_F(ContactState, MovesBetweenFreeCheckpointsNeedNoSolve) {
  run_all(plate_variant(dir_, {{kBundledBox, "box = [[1.8, 1.8, -1.0], [2.2, 2.2, -0.8]]"},
                               {"max_force = 0.5", "max_force = 0.03"}}),
          {"--max-transitions", "400"});
  Catalogue cat(state() / "catalogue.sqlite", OpenMode::kReadOnly);
  std::map<CheckpointId, Checkpoint> checkpoints;
  int free = 0;
  for (const Checkpoint& c : cat.read_all_checkpoints()) {
    checkpoints.emplace(c.id, c);
    if (c.classification == CheckpointClass::kFree) {
      ++free;
      EXPECT_EQ(c.ijk[2], 0);  // z = -1.0 (the rest centre); z = -0.8 touches the plate at rest
    }
  }
  EXPECT_EQ(free, 9);
  int trivial = 0, solved_in = 0;
  for (const Transition& t : cat.read_all_transitions()) {
    if (t.outcome != TransitionOutcome::kReached) continue;
    const Configuration source = cat.read_configuration(t.source);
    const Configuration target = cat.read_configuration(t.target);
    const bool from_free =
        checkpoints.at(source.checkpoint).classification == CheckpointClass::kFree;
    const bool to_free = checkpoints.at(target.checkpoint).classification == CheckpointClass::kFree;
    if (from_free && to_free && !source.blob) {
      EXPECT_EQ(t.substeps, 0);
      EXPECT_EQ(t.newton_iterations, 0);
      EXPECT_FALSE(target.blob.has_value());
      EXPECT_EQ(target.level.value(), 0);
      ++trivial;
    } else if (from_free && !to_free) {
      EXPECT_GT(t.substeps, 0);
      EXPECT_TRUE(target.blob.has_value());
      ++solved_in;
    }
  }
  // 9 free check-points in a 3 x 3 layer: 8 x 3 + 4 x 2 ... = 40 ordered neighbour pairs.
  EXPECT_EQ(trivial, 40);
  EXPECT_GT(solved_in, 0);
}

// Contact expansion is as deterministic as grab expansion: 1 and 2 threads give the same
// decisions, vectors and (sticking) touched sets; both friction models.
class ContactThreads : public ContactState, public ::testing::WithParamInterface<const char*> {};

TEST_P(ContactThreads, ThreadCountDoesNotChangeTheStateSpace) {
  const std::string scene = plate_variant(
      dir_, {{kBundledBox, "box = [[1.8, 1.8, -1.0], [2.2, 2.2, -0.8]]"},
             {"max_force = 0.5", "max_force = 0.03"},
             {"friction = \"none\"", std::string("friction = \"") + GetParam() + "\""}});
  const bool stick = std::string(GetParam()) == "stick";
  std::vector<fs::path> states;
  for (int threads : {1, 2}) {
    const fs::path state = dir_ / ("state" + std::to_string(threads));
    ASSERT_EQ(import_stage(state, scene, dir_).exit_code, 0);
    ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
    const StageResult e = expand_stage(state, threads, dir_, {"--max-transitions", "300"});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    states.push_back(state);
  }
  const Snapshot a = snapshot(states[0]);
  expect_same_decisions(a, snapshot(states[1]));
  EXPECT_EQ(max_vector_difference(states[0], states[1], a.configurations), 0.0);
  BlobStore b0(states[0] / "blobs"), b1(states[1] / "blobs");
  int touching = 0;
  for (const Configuration& c : a.configurations) {
    if (!c.blob) continue;
    if (stick) {
      const auto t0 = b0.read(c.blob->segment, c.blob->name + "/touched");
      EXPECT_EQ(t0, b1.read(c.blob->segment, c.blob->name + "/touched"));
    }
    touching += force_of(c).norm() > 0 ? 1 : 0;
  }
  EXPECT_GT(touching, 5);
}

INSTANTIATE_TEST_SUITE_P(Friction, ContactThreads, ::testing::Values("none", "stick"));

}  // namespace
}  // namespace hapstate::test_util
