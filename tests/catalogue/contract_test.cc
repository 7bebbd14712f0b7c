// The catalogue contract: every verb, on a file catalogue and on ":memory:".
#include "../blobs/temp_dir.h"
#include "catalogue/catalogue.h"
#include "catalogue/transaction.h"
#include "util/error.h"

#include "../common/expect_input_error.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace hapstate {
namespace {

using test_util::expect_input_error;

class CatalogueContract : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (GetParam() == "file") {
      dir_ = std::make_unique<test_util::TempDir>("catalogue");
      cat_ = std::make_unique<Catalogue>(dir_->path() / "catalogue.sqlite", OpenMode::kCreate);
    } else {
      cat_ = std::make_unique<Catalogue>(":memory:", OpenMode::kCreate);
    }
  }
  Catalogue& cat() { return *cat_; }

  CheckpointId add_checkpoint(int i, int j, int k) {
    Checkpoint c;
    c.ijk = {i, j, k};
    c.position = {0.5 * i, 0.5 * j, 0.5 * k};
    c.classification = CheckpointClass::kWorkspace;
    return cat().insert_checkpoint(c);
  }

  Configuration make_config(CheckpointId cp, int level, int wave) {
    Configuration c;
    c.checkpoint = cp;
    c.level = Level(level);
    c.wave = wave;
    c.force = {0.1 * level, -0.2, 1.5e-3};
    for (int a = 0; a < 9; ++a) c.stiffness[a] = 10.0 * a - 3.25;
    c.expandable = true;
    c.summary = {1.0, -2.5, 3.0e-7};
    return c;
  }

  std::unique_ptr<test_util::TempDir> dir_;
  std::unique_ptr<Catalogue> cat_;
};

TEST_P(CatalogueContract, FreshCatalogueIsEmptyAndCurrent) {
  EXPECT_EQ(cat().schema_version(), Catalogue::supported_schema_version());
  EXPECT_EQ(Catalogue::supported_schema_version(), 10);
  EXPECT_FALSE(cat().read_scene());
  EXPECT_EQ(cat().num_checkpoints(), 0);
  EXPECT_EQ(cat().num_configurations(), 0);
  EXPECT_EQ(cat().num_transitions(), 0);
  EXPECT_FALSE(cat().max_wave());
  EXPECT_EQ(cat().max_config_id(), kInvalidConfigId);
  EXPECT_TRUE(cat().referenced_segments().empty());
  EXPECT_EQ(cat().integrity_check(), "ok");
}

TEST_P(CatalogueContract, SceneRoundTripAndReplace) {
  SceneRecord scene;
  scene.text = "[mesh]\nfile = \"beam.msh\"\n";
  scene.hash = content_hash(scene.text);
  scene.mesh_file = "beam.msh";
  scene.mesh_hash = ContentHash{0xfedcba9876543210ULL};
  scene.mesh_nodes = 1234;
  scene.mesh_elements = 4567;
  scene.mesh_surface_triangles = 890;
  scene.bbox_min = {-1.0, -2.0, -3.0};
  scene.bbox_max = {1.0, 2.0, 3.5};
  scene.volume = 41.75;
  cat().write_scene(scene);
  EXPECT_EQ(cat().read_scene(), scene);
  scene.mesh_nodes = 99;
  cat().write_scene(scene);
  EXPECT_EQ(cat().read_scene()->mesh_nodes, 99);
}

TEST_P(CatalogueContract, StageRunsRecordInputsAndOutcome) {
  StageRun run;
  run.stage = "grid";
  run.inputs = {{"mesh", ContentHash{2}}, {"scene", ContentHash{1}}};
  run.parameters = "spacing = 0.25";
  run.started = TimeMs(std::chrono::milliseconds(1700000000123));
  const StageRunId first = cat().insert_stage_run(run);
  EXPECT_FALSE(cat().last_successful_stage_run("grid"));
  cat().update_stage_run_end(first, StageOutcome::kOk,
                             TimeMs(std::chrono::milliseconds(1700000005000)), "42 check-points");
  const StageRun back = cat().read_stage_run(first);
  EXPECT_EQ(back.stage, "grid");
  EXPECT_EQ(back.inputs, run.inputs);
  EXPECT_EQ(back.parameters, "spacing = 0.25");
  EXPECT_EQ(back.hapstate_version, "0.1.0");
  EXPECT_EQ(back.started.time_since_epoch().count(), 1700000000123);
  ASSERT_TRUE(back.ended);
  EXPECT_EQ(back.ended->time_since_epoch().count(), 1700000005000);
  EXPECT_EQ(back.outcome, StageOutcome::kOk);
  EXPECT_EQ(back.message, "42 check-points");

  run.outcome = StageOutcome::kFailed;
  const StageRunId second = cat().insert_stage_run(run);
  EXPECT_GT(second, first);
  run.stage = "expand";
  cat().insert_stage_run(run);
  EXPECT_EQ(cat().read_stage_runs("grid").size(), 2u);
  EXPECT_EQ(cat().read_stage_runs("grid")[1].outcome, StageOutcome::kFailed);
  EXPECT_EQ(cat().last_successful_stage_run("grid")->id, first);
  EXPECT_FALSE(cat().last_successful_stage_run("expand"));
  expect_input_error(
      [&] { cat().update_stage_run_end(StageRunId(999), StageOutcome::kOk, {}, ""); },
      "no stage_run with id 999");
  // A duplicate input name fails the whole insert: the run row is not left behind.
  run.inputs = {{"scene", ContentHash{1}}, {"scene", ContentHash{3}}};
  const auto runs_before = cat().read_stage_runs("expand").size();
  expect_input_error([&] { cat().insert_stage_run(run); }, "UNIQUE constraint failed");
  EXPECT_EQ(cat().read_stage_runs("expand").size(), runs_before);
}

TEST_P(CatalogueContract, CheckpointVerbs) {
  const CheckpointId a = add_checkpoint(0, 0, 0);
  const CheckpointId b = add_checkpoint(1, 0, -2);
  EXPECT_NE(a, b);
  EXPECT_EQ(cat().num_checkpoints(), 2);
  const Checkpoint read = cat().read_checkpoint(b);
  EXPECT_EQ(read.id, b);
  EXPECT_EQ(read.ijk, (std::array<int, 3>{1, 0, -2}));
  EXPECT_EQ(read.position, (std::array<double, 3>{0.5, 0.0, -1.0}));
  EXPECT_EQ(read.classification, CheckpointClass::kWorkspace);
  EXPECT_EQ(cat().find_checkpoint({1, 0, -2})->id, b);
  EXPECT_FALSE(cat().find_checkpoint({5, 5, 5}));
  EXPECT_TRUE(cat().exists_checkpoint(a));
  EXPECT_FALSE(cat().exists_checkpoint(CheckpointId(77)));
  EXPECT_EQ(cat().read_all_checkpoints().size(), 2u);
  expect_input_error([&] { add_checkpoint(1, 0, -2); }, "UNIQUE constraint failed: checkpoint.i");
  expect_input_error([&] { cat().read_checkpoint(CheckpointId(77)); }, "no checkpoint with id 77");
}

TEST_P(CatalogueContract, ConfigurationVerbs) {
  const CheckpointId cp = add_checkpoint(0, 0, 0);
  const CheckpointId other = add_checkpoint(0, 0, 1);
  Configuration zero = make_config(cp, 0, 0);
  zero.blob = BlobRef{SegmentId{3}, "c1"};
  const ConfigId z = cat().insert_configuration(zero);
  zero.id = z;
  EXPECT_EQ(cat().read_configuration(z), zero);

  Configuration fixed = make_config(cp, 1, 1);
  fixed.id = ConfigId(100);  // id chosen by the stage
  fixed.blob = BlobRef{SegmentId{4}, "c100"};
  EXPECT_EQ(cat().insert_configuration(fixed), ConfigId(100));
  Configuration stored = make_config(other, 0, 1);
  stored.expandable = false;  // |force| > F_max
  const ConfigId s = cat().insert_configuration(stored);
  EXPECT_EQ(s, ConfigId(101));

  EXPECT_EQ(cat().num_configurations(), 3);
  EXPECT_EQ(cat().max_config_id(), ConfigId(101));
  EXPECT_EQ(*cat().max_wave(), 1);
  EXPECT_EQ(cat().next_level(cp), Level(2));
  EXPECT_EQ(cat().next_level(CheckpointId(55)), Level(0));
  const auto at = cat().configurations_at(cp);
  ASSERT_EQ(at.size(), 2u);
  EXPECT_EQ(at[0].level, Level(0));
  EXPECT_EQ(at[1].id, ConfigId(100));
  EXPECT_EQ(at[1].blob, (BlobRef{SegmentId{4}, "c100"}));
  EXPECT_FALSE(cat().read_configuration(s).blob);

  ASSERT_EQ(cat().frontier(1).size(), 1u);  // the non-expandable one is not in it
  EXPECT_EQ(cat().frontier(1)[0].id, ConfigId(100));
  cat().update_configuration_status(ConfigId(100), ConfigStatus::kExpanded);
  EXPECT_TRUE(cat().frontier(1).empty());
  EXPECT_EQ(cat().read_configuration(ConfigId(100)).status, ConfigStatus::kExpanded);
  EXPECT_EQ(cat().frontier(0).size(), 1u);
  EXPECT_EQ(cat().referenced_segments(), (std::set<SegmentId>{{3}, {4}}));
  EXPECT_TRUE(cat().exists_configuration(s));
  EXPECT_FALSE(cat().exists_configuration(ConfigId(5)));

  expect_input_error([&] { cat().insert_configuration(make_config(cp, 1, 2)); },
                     "UNIQUE constraint failed: configuration.checkpoint, configuration.level");
  expect_input_error([&] { cat().insert_configuration(make_config(CheckpointId(999), 0, 0)); },
                     "FOREIGN KEY constraint failed");
  expect_input_error([&] { cat().read_configuration(ConfigId(5)); }, "no configuration with id 5");
  expect_input_error([&] { cat().update_configuration_status(ConfigId(5), ConfigStatus::kMerged); },
                     "no configuration with id 5");
  EXPECT_EQ(cat().num_configurations(), 3);
}

TEST_P(CatalogueContract, TransitionVerbsAndUniqueSourceDirection) {
  const CheckpointId cp = add_checkpoint(0, 0, 0);
  const CheckpointId next = add_checkpoint(0, 0, 1);
  const ConfigId a = cat().insert_configuration(make_config(cp, 0, 0));
  const ConfigId b = cat().insert_configuration(make_config(next, 0, 1));

  Transition reached;
  reached.source = a;
  reached.direction = Direction::from_offset(0, 0, 1);
  reached.target = b;
  reached.substeps = 4;
  reached.newton_iterations = 17;
  reached.final_residual = 3.5e-10;
  reached.wall_ms = 12.25;
  cat().insert_transition(reached);

  Transition failed;
  failed.source = a;
  failed.direction = Direction(2);
  failed.outcome = TransitionOutcome::kFailed;
  failed.substeps = 16;
  failed.newton_iterations = 30;
  failed.final_residual = 0.75;
  failed.wall_ms = 80.0;
  failed.failure_reason = "element inversion (J <= 0) after 4 cut-backs";
  cat().insert_transition(failed);

  Transition outside;
  outside.source = a;
  outside.direction = Direction(0);
  outside.outcome = TransitionOutcome::kOutsideGrid;
  cat().insert_transition(outside);

  EXPECT_EQ(cat().read_transition(a, reached.direction), reached);
  EXPECT_EQ(cat().read_transition(a, Direction(2)), failed);
  EXPECT_FALSE(cat().read_transition(a, Direction(5)));
  const auto of_a = cat().transitions_of(a);
  ASSERT_EQ(of_a.size(), 3u);
  EXPECT_EQ(of_a[0], outside);
  EXPECT_EQ(of_a[1], failed);
  EXPECT_EQ(of_a[2], reached);
  EXPECT_TRUE(cat().transitions_of(b).empty());
  EXPECT_EQ(cat().num_transitions(), 3);
  EXPECT_EQ(cat().num_failed_transitions(), 1);
  EXPECT_EQ(cat().read_all_transitions().size(), 3u);

  Transition again = reached;
  again.target = a;
  expect_input_error([&] { cat().insert_transition(again); },
                     "UNIQUE constraint failed: transition.source, transition.direction");
  Transition no_target = reached;
  no_target.direction = Direction(7);
  no_target.target = kInvalidConfigId;
  expect_input_error([&] { cat().insert_transition(no_target); }, "CHECK constraint failed");
  Transition dangling = reached;
  dangling.direction = Direction(8);
  dangling.target = ConfigId(12345);
  expect_input_error([&] { cat().insert_transition(dangling); }, "FOREIGN KEY constraint failed");
  EXPECT_EQ(cat().num_transitions(), 3);
  EXPECT_EQ(cat().num_foreign_key_violations(), 0);
  EXPECT_EQ(cat().integrity_check(), "ok");
}

TEST_P(CatalogueContract, TransactionCommitsOrRollsBack) {
  const CheckpointId cp = add_checkpoint(0, 0, 0);
  try {
    Transaction tx(cat());
    cat().insert_configuration(make_config(cp, 0, 0));
    add_checkpoint(3, 3, 3);
    EXPECT_EQ(cat().num_configurations(), 1);  // visible inside the transaction
    throw std::runtime_error("solver exploded");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(cat().num_configurations(), 0);
  EXPECT_EQ(cat().num_checkpoints(), 1);

  {
    Transaction tx(cat());
    EXPECT_THROW(Transaction nested(cat()), std::logic_error);
    cat().insert_configuration(make_config(cp, 0, 0));
    tx.commit();
    EXPECT_THROW(tx.commit(), std::logic_error);
  }
  EXPECT_EQ(cat().num_configurations(), 1);
  {
    Transaction tx(cat());  // destroyed without commit: rolled back
    cat().insert_configuration(make_config(cp, 1, 0));
  }
  EXPECT_EQ(cat().num_configurations(), 1);
  EXPECT_EQ(cat().integrity_check(), "ok");
}

INSTANTIATE_TEST_SUITE_P(Backends, CatalogueContract, ::testing::Values("file", "memory"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace hapstate
