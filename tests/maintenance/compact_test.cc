// Compaction of a synthetic state directory: exactly the duplicates are merged, transitions
// rewritten, blobs repacked, garbage dropped, and a crash at either commit point is harmless.
#include "maintenance/compact.h"
#include "../blobs/temp_dir.h"
#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "catalogue/catalogue.h"
#include "maintenance/level_compare.h"
#include "maintenance/level_merge.h"
#include "scene/scene.h"
#include "statedir/state_dir.h"
#include "synthetic_state.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace hapstate {
namespace {

using test_util::TempDir;

// hapstate-compact on `state` with `options` (run_compact with options.state set).
CompactReport compact_state(const std::filesystem::path& state, CompactOptions options) {
  options.state = state;
  return run_compact(options);
}

struct SimulatedCrash : std::runtime_error {
  SimulatedCrash() : std::runtime_error("simulated crash") {}
};

CompactOptions crash_at(std::string point) {
  CompactOptions o;
  o.fault_point = [point](std::string_view at) {
    if (at == point) throw SimulatedCrash();
  };
  return o;
}

// Every live configuration's vectors can be read and equal what was written.
void expect_all_blobs_readable(const std::filesystem::path& dir) {
  Catalogue cat(dir / "catalogue.sqlite", OpenMode::kReadOnly);
  BlobStore blobs(dir / "blobs");
  for (const Configuration& c : cat.read_all_configurations()) {
    if (!c.blob) continue;
    EXPECT_EQ(blobs.read(c.blob->segment, c.blob->name + "/u"),
              test_util::synthetic_u(c.id.value()))
        << "configuration " << c.id.value();
  }
}

void expect_consistent(const std::filesystem::path& dir) {
  Catalogue cat(dir / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.integrity_check(), "ok");
  EXPECT_EQ(cat.num_foreign_key_violations(), 0);
  BlobStore blobs(dir / "blobs");
  EXPECT_TRUE(blobs.unreferenced_segments(cat.referenced_segments()).empty());
}

TEST(LevelCompare, DistanceInToleranceUnitsWithZeroStates) {
  const LevelTolerances tol{0.01, 0.05};
  const ConfigVectors a{{0.0, 1.0}, {}, {0.0, 0.0, 0.0}, {}, {}};
  EXPECT_DOUBLE_EQ(compaction_level_distance(a, {{0.005, 1.0}, {}, {0.0, 0.0, 0.0}, {}, {}}, tol),
                   0.5);
  EXPECT_DOUBLE_EQ(compaction_level_distance(a, {{0.0, 1.0}, {}, {0.03, 0.04, 0.0}, {}, {}}, tol),
                   1.0);
  EXPECT_TRUE(std::isinf(compaction_level_distance(a, {{0.0}, {}, {0.0, 0.0, 0.0}, {}, {}}, tol)));
  // No blob: zeros of the other's length.
  EXPECT_DOUBLE_EQ(
      compaction_level_distance({}, {{0.004, -0.002}, {}, {0.0, 0.0, 0.01}, {}, {}}, tol), 0.4);
}

TEST(LevelCompare, BoundFromSummariesAndForces) {
  const LevelTolerances tol{0.01, 0.05};
  Configuration a, b;
  a.summary = {0.0, 0.0};
  b.summary = {0.0, -0.0099};
  EXPECT_LE(compaction_distance_bound(a, b, 3, tol), 1.0);
  b.summary = {0.0, -0.0101};
  EXPECT_GT(compaction_distance_bound(a, b, 3, tol), 1.0);
  b.summary = a.summary;
  b.force = {0.08, 0.0, 0.0};  // < sqrt(3) * 0.05 = 0.0866: h may still be within tolerance
  EXPECT_LE(compaction_distance_bound(a, b, 3, tol), 1.0);
  b.force = {0.09, 0.0, 0.0};
  EXPECT_GT(compaction_distance_bound(a, b, 3, tol), 1.0);
}

TEST(FindLevelMerges, FindsExactlyTheDuplicates) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
  BlobStore blobs(dir.path() / "blobs");
  MergeSearchStats stats;
  const auto merges =
      find_level_merges(cat, blobs, {test_util::kUTol, test_util::kHTol}, {}, &stats);
  ASSERT_EQ(merges.size(), 2u);
  EXPECT_EQ(merges[0].kept, ConfigId(3));
  EXPECT_EQ(merges[0].merged, ConfigId(4));
  EXPECT_NEAR(merges[0].distance, 0.5, 1e-9);
  EXPECT_EQ(merges[1].kept, ConfigId(6));
  EXPECT_EQ(merges[1].merged, ConfigId(8));
  EXPECT_NEAR(merges[1].distance, 0.99, 1e-9);
  EXPECT_EQ(stats.compared, 4);          // c4-c3, c5-c3, c7-c6, c8-c6
  EXPECT_EQ(stats.bound_rejections, 1);  // c2-c1 (1 N and up to 0.1 apart at the sample nodes)
}

TEST(Compact, MergesRewritesRepacksAndShrinks) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  const CompactReport r = compact_state(dir.path(), {});
  EXPECT_FALSE(r.unchanged());
  EXPECT_EQ(r.merged_levels, 2);
  EXPECT_EQ(r.retargeted_transitions, 3);  // c2->c4, c6->c4, c4->c8
  EXPECT_EQ(r.moved_transitions, 1);       // c4's outside-grid direction 13 given to c3
  EXPECT_EQ(r.garbage_segments, 0);
  EXPECT_EQ(r.repacked_configurations, 5);  // c2, c3, c5, c6, c7
  EXPECT_EQ(r.new_segments, 1);
  EXPECT_EQ(r.dead_vectors, 6);  // c4 and c8: u, t, h
  EXPECT_EQ(r.before.segments, 3);
  EXPECT_EQ(r.after.segments, 1);
  EXPECT_LT(r.after.blob_bytes, r.before.blob_bytes);
  EXPECT_LT(r.after.total(), r.before.total());

  Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.read_configuration(ConfigId(4)).status, ConfigStatus::kMerged);
  EXPECT_EQ(cat.read_configuration(ConfigId(8)).status, ConfigStatus::kMerged);
  EXPECT_FALSE(cat.read_configuration(ConfigId(4)).blob.has_value());
  for (int id : {2, 3, 5, 6, 7}) {
    const Configuration c = cat.read_configuration(ConfigId(id));
    EXPECT_NE(c.status, ConfigStatus::kMerged) << id;
    ASSERT_TRUE(c.blob.has_value()) << id;
    EXPECT_EQ(c.blob->segment, SegmentId{4}) << id;
  }
  EXPECT_EQ(cat.read_transition(ConfigId(2), Direction(21))->target, ConfigId(3));
  EXPECT_EQ(cat.read_transition(ConfigId(6), Direction(4))->target, ConfigId(3));
  EXPECT_EQ(cat.read_transition(ConfigId(4), Direction(21))->target, ConfigId(6));
  EXPECT_EQ(cat.read_transition(ConfigId(3), Direction(13))->outcome,
            TransitionOutcome::kOutsideGrid);
  EXPECT_FALSE(cat.read_transition(ConfigId(4), Direction(13)).has_value());
  EXPECT_EQ(cat.num_transitions(), 10);
  const auto target_4 =
      cat.query_read_only("SELECT count(*) FROM transition WHERE target IN (4, 8)");
  EXPECT_EQ(std::get<std::int64_t>(target_4.rows[0][0]), 0);

  BlobStore blobs(dir.path() / "blobs");
  EXPECT_EQ(blobs.list_segments(), std::vector<SegmentId>{SegmentId{4}});
  EXPECT_EQ(blobs.list_vectors(SegmentId{4}).size(), 16u);  // 5 x (u, t, h) + c3/visual
  EXPECT_EQ(blobs.precision_of(SegmentId{4}, "c3/visual"), Precision::kFloat32);
  EXPECT_EQ(blobs.read_float32(SegmentId{4}, "c3/visual"),
            (std::vector<float>{0.5f, -1.25f, 3.0f}));
  EXPECT_EQ(blobs.provenance(SegmentId{4}).stage, "compact");

  const auto runs = cat.read_stage_runs("compact");
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].outcome, StageOutcome::kOk);
  expect_all_blobs_readable(dir.path());
  expect_consistent(dir.path());
}

TEST(Compact, SecondRunHasNothingToDo) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  compact_state(dir.path(), {});
  const CompactReport r = compact_state(dir.path(), {});
  EXPECT_TRUE(r.unchanged());
  EXPECT_EQ(r.merged_levels, 0);
  EXPECT_EQ(r.new_segments, 0);
  EXPECT_EQ(r.garbage_segments, 0);
  EXPECT_EQ(r.before.segments, 1);
  EXPECT_EQ(r.after.segments, 1);
  EXPECT_EQ(r.after.blob_bytes, r.before.blob_bytes);
  EXPECT_NE(r.text().find("nothing to do"), std::string::npos);
  Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
  const auto runs = cat.read_stage_runs("compact");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[1].outcome, StageOutcome::kUnchanged);
  expect_consistent(dir.path());
}

TEST(Compact, DryRunChangesNothing) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  CompactOptions o;
  o.dry_run = true;
  const CompactReport r = compact_state(dir.path(), o);
  EXPECT_EQ(r.merged_levels, 2);
  EXPECT_EQ(r.repacked_configurations, 5);
  // The dry run predicts the segments of the real run.
  const std::int64_t predicted = r.after.segments;
  EXPECT_NE(r.text().find("would do: "), std::string::npos) << r.text();
  {
    TempDir copy("compact-copy");
    std::filesystem::copy(dir.path(), copy.path(),
                          std::filesystem::copy_options::recursive |
                              std::filesystem::copy_options::overwrite_existing);
    const CompactReport real = compact_state(copy.path(), CompactOptions{});
    EXPECT_EQ(real.new_segments, r.new_segments);
    EXPECT_EQ(real.after.segments, predicted);
  }
  Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.read_configuration(ConfigId(4)).status, ConfigStatus::kOpen);
  EXPECT_TRUE(cat.read_stage_runs("compact").empty());
  EXPECT_EQ(BlobStore(dir.path() / "blobs").list_segments().size(), 3u);
}

TEST(Compact, CrashBeforeTheCommitLeavesTheOriginalState) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  EXPECT_THROW(compact_state(dir.path(), crash_at("segments-written")), SimulatedCrash);
  {
    Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.read_configuration(ConfigId(4)).status, ConfigStatus::kOpen);
    EXPECT_EQ(cat.read_configuration(ConfigId(4)).blob->segment, SegmentId{2});
    EXPECT_EQ(cat.read_transition(ConfigId(2), Direction(21))->target, ConfigId(4));
    EXPECT_EQ(cat.integrity_check(), "ok");
    // The new segment was written and is now an orphan.
    BlobStore blobs(dir.path() / "blobs");
    EXPECT_EQ(blobs.unreferenced_segments(cat.referenced_segments()).size(), 1u);
  }
  expect_all_blobs_readable(dir.path());
  const CompactReport r = compact_state(dir.path(), {});
  EXPECT_EQ(r.garbage_segments, 1);
  EXPECT_EQ(r.merged_levels, 2);
  EXPECT_EQ(r.after.segments, 1);
  expect_all_blobs_readable(dir.path());
  expect_consistent(dir.path());
}

TEST(Compact, CrashAfterTheCommitLeavesGarbageForTheNextRun) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  EXPECT_THROW(compact_state(dir.path(), crash_at("committed")), SimulatedCrash);
  expect_all_blobs_readable(dir.path());  // through the new references
  {
    Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.read_configuration(ConfigId(4)).status, ConfigStatus::kMerged);
    EXPECT_EQ(
        BlobStore(dir.path() / "blobs").unreferenced_segments(cat.referenced_segments()).size(),
        3u);
  }
  const CompactReport r = compact_state(dir.path(), {});
  EXPECT_EQ(r.garbage_segments, 3);
  EXPECT_EQ(r.merged_levels, 0);
  EXPECT_EQ(r.new_segments, 0);
  EXPECT_EQ(r.after.segments, 1);
  expect_consistent(dir.path());
}

TEST(Compact, MissingStateOrSceneIsAnInputError) {
  TempDir dir("compact");
  EXPECT_THROW(compact_state(dir.path() / "nope", {}), InputError);
  EXPECT_THROW(compact_state(dir.path(), {}), InputError);  // no catalogue.sqlite
  { Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kCreate); }
  try {
    compact_state(dir.path(), {});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no scene stored"), std::string::npos) << e.what();
  }
}

TEST(Compact, RefusedWhileTheStateIsLocked) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  {
    StateDirLock held(StateDir{dir.path()});
    try {
      compact_state(dir.path(), {});
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("another hapstate stage"), std::string::npos)
          << e.what();
    }
    CompactOptions dry;
    dry.dry_run = true;
    EXPECT_EQ(compact_state(dir.path(), dry).merged_levels, 2);  // a dry run only reads
  }
  EXPECT_EQ(compact_state(dir.path(), {}).merged_levels, 2);
}

TEST(Compact, SmallSegmentCapGivesSeveralSegments) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  CompactOptions o;
  o.repack.max_segment_values = 1200;  // two configurations (549 values each) per segment
  const CompactReport r = compact_state(dir.path(), o);
  EXPECT_EQ(r.new_segments, 3);  // {c2, c3}, {c5, c6}, {c7}
  EXPECT_EQ(r.after.segments, 3);
  expect_all_blobs_readable(dir.path());
  EXPECT_TRUE(compact_state(dir.path(), o).unchanged());
}

// The midpoint vectors of a transition move with it: repacked beside the configurations and
// repointed (a merged configuration keeps its transition rows, and they their vectors); a
// midpoint group no row references is dead.
TEST(Compact, MidpointVectorsAreRepackedWithTheirTransitions) {
  TempDir dir("compact");
  test_util::write_synthetic_state(dir.path());
  const std::vector<float> kept_u = {0.5f, -0.25f, 2.0f};
  const std::vector<float> kept_slopes = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  {
    Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadWrite);
    BlobStore blobs(dir.path() / "blobs");
    const SegmentId id = blobs.next_segment_id();
    SegmentWriter writer(dir.path() / "blobs", id, SegmentProvenance{"", "", "expand"});
    writer.write("m2_21/u", std::span<const float>(kept_u));
    writer.write("m2_21/du_dp", std::span<const float>(kept_slopes));
    writer.write("m4_21/u", std::span<const float>(kept_u));  // c4 is merged into c3
    writer.write("m9_3/u", std::span<const float>(kept_u));   // no such transition
    writer.write("m4_13/u", std::span<const float>(kept_u));  // a row the merge gives to c3
    writer.close();
    ASSERT_TRUE(cat.update_transition_midpoint_blob(ConfigId(2), Direction(21), {id, "m2_21"}));
    ASSERT_TRUE(cat.update_transition_midpoint_blob(ConfigId(4), Direction(21), {id, "m4_21"}));
    ASSERT_TRUE(cat.update_transition_midpoint_blob(ConfigId(4), Direction(13), {id, "m4_13"}));
  }
  const CompactReport r = compact_state(dir.path(), {});
  EXPECT_EQ(r.repacked_configurations, 5);
  EXPECT_EQ(r.dead_vectors, 7);  // c4 and c8: u, t, h; m9_3/u
  EXPECT_EQ(r.after.segments, 1);
  Catalogue cat(dir.path() / "catalogue.sqlite", OpenMode::kReadOnly);
  const auto t = cat.read_transition(ConfigId(2), Direction(21));
  ASSERT_TRUE(t && t->midpoint_blob);
  const SegmentId packed = cat.read_configuration(ConfigId(2)).blob->segment;
  EXPECT_EQ(t->midpoint_blob->segment, packed);
  EXPECT_EQ(t->midpoint_blob->name, "m2_21");
  BlobStore blobs(dir.path() / "blobs");
  EXPECT_EQ(blobs.read_float32(packed, "m2_21/u"), kept_u);
  EXPECT_EQ(blobs.read_float32(packed, "m2_21/du_dp"), kept_slopes);
  EXPECT_EQ(cat.read_transition(ConfigId(4), Direction(21))->midpoint_blob->segment, packed);
  EXPECT_TRUE(blobs.contains(packed, "m4_21/u"));
  EXPECT_FALSE(blobs.contains(packed, "m9_3/u"));
  const auto moved = cat.read_transition(ConfigId(3), Direction(13));
  ASSERT_TRUE(moved && moved->midpoint_blob);
  EXPECT_EQ(*moved->midpoint_blob, (BlobRef{packed, "m4_13"}));
  EXPECT_EQ(blobs.read_float32(packed, "m4_13/u"), kept_u);
  expect_all_blobs_readable(dir.path());
  expect_consistent(dir.path());
  EXPECT_TRUE(compact_state(dir.path(), {}).unchanged());
}

}  // namespace
}  // namespace hapstate
