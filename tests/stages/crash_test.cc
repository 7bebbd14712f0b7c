// kill -9 at random moments of hapstate-expand, resume each time: the final catalogue equals an
// uninterrupted run's, SQLite finds no corruption and no orphan segment is left.
#include "beam_state.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"

#include <chrono>
#include <random>
#include <thread>

namespace hapstate::test_util {
namespace {

class Crash : public StageTest {};

TEST_F(Crash, KilledAndResumedRunEqualsAnUninterruptedOne) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 2, dir_);
  ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
  ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);

  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay_ms(150, 900);  // process start-up included
  int kills = 0, finished_early = 0;
  for (int round = 0; round < 5; ++round) {
    const pid_t pid = start_stage(HAPSTATE_EXPAND_EXE, expand_args(state, 2), dir_);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    if (::kill(pid, SIGKILL) == 0) ++kills;
    const StageResult r = wait_stage(pid, dir_);
    if (r.exit_code == 0) ++finished_early;  // it ended before the signal
    // After every crash the directory is consistent.
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.integrity_check(), "ok");
    EXPECT_EQ(cat.num_foreign_key_violations(), 0);
  }
  EXPECT_GE(kills, 1);
  const StageResult last = expand_stage(state, 2, dir_);
  ASSERT_EQ(last.exit_code, 0) << last.err;

  const Snapshot a = snapshot(reference), b = snapshot(state);
  expect_same_decisions(a, b);
  EXPECT_LE(max_vector_difference(reference, state, a.configurations), 1e-12);
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.integrity_check(), "ok");
  BlobStore blobs(state / "blobs");
  EXPECT_TRUE(blobs.unreferenced_segments(cat.referenced_segments()).empty());
  // The runs that died are recorded as interrupted; none is left "running".
  int interrupted = 0;
  for (const StageRun& run : cat.read_stage_runs("expand")) {
    EXPECT_NE(run.outcome, StageOutcome::kRunning);
    if (run.outcome == StageOutcome::kFailed) {
      ++interrupted;
      EXPECT_NE(run.message.find("interrupted"), std::string::npos) << run.message;
    }
  }
  EXPECT_GE(interrupted, 1);
  EXPECT_LE(interrupted, kills);
  std::printf("[ info ] %d kills, %d runs ended before the signal\n", kills, finished_early);
}

TEST_F(Crash, ChunkedRunsWithLimitsEqualOneRun) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 1, dir_);
  ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
  ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
  // A time limit ends the run cleanly at a batch boundary too.
  const StageResult timed = expand_stage(state, 2, dir_, {"--max-seconds", "0.5"});
  ASSERT_EQ(timed.exit_code, 0) << timed.err;
  EXPECT_NE(timed.out.find("partial"), std::string::npos) << timed.out;
  int partial = 1;
  for (int round = 0; round < 100; ++round) {
    const StageResult r = expand_stage(state, 2, dir_, {"--max-transitions", "100"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (r.out.find("partial") == std::string::npos) break;
    ++partial;
  }
  EXPECT_GE(partial, 3);
  expect_same_decisions(snapshot(reference), snapshot(state));
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  int partial_runs = 0;
  for (const StageRun& run : cat.read_stage_runs("expand"))
    partial_runs += run.outcome == StageOutcome::kPartial;
  EXPECT_EQ(partial_runs, partial);
}

}  // namespace
}  // namespace hapstate::test_util
