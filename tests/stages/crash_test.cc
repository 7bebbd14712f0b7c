// kill -9 at random moments of hapstate-expand, resume each time: the final catalogue equals an
// uninterrupted run's, SQLite finds no corruption and no orphan segment is left.
#include "beam_state.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "maintenance/inspect.h"

#include <chrono>
#include <initializer_list>
#include <optional>
#include <random>
#include <thread>

#include <sys/wait.h>

namespace hapstate::test_util {
namespace {

class Crash : public StageTest {
 protected:
  static std::size_t expand_runs(const fs::path& state) {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    return cat.read_stage_runs("expand").size();
  }

  // Waits (at most 60 s) until the catalogue of `state` holds more than `before` expand runs
  // (the process has recorded its run, so a kill from now on interrupts a run) or process `pid`
  // has ended (left unreaped for wait_stage).
  static void wait_for_run_row(const fs::path& state, std::size_t before, pid_t pid) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < until) {
      siginfo_t info{};
      if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
          info.si_pid == pid)
        return;  // ended
      if (expand_runs(state) > before) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  // Imports and grids the beam into dir_/state, starts hapstate-expand on one thread, sends
  // `signals` 250 ms later (5 ms apart) and waits for it. The result is nullopt if the
  // expansion ended before the first signal (nothing to test).
  std::optional<StageResult> expand_and_signal(std::initializer_list<int> signals) {
    const fs::path state = dir_ / "state";
    EXPECT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
    EXPECT_EQ(grid_stage(state, dir_).exit_code, 0);
    const pid_t pid = start_stage(HAPSTATE_EXPAND_EXE, expand_args(state, 1), dir_);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    bool first = true;
    for (int signal : signals) {
      if (!first) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const int sent = ::kill(pid, signal);
      if (first) {
        EXPECT_EQ(sent, 0);
      }
      first = false;
    }
    const StageResult r = wait_stage(pid, dir_);
    if (r.exit_code == 0) return std::nullopt;
    return r;
  }
};

TEST_F(Crash, KilledAndResumedRunEqualsAnUninterruptedOne) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 2, dir_);
  ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
  ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);

  std::mt19937 rng(20261122);
  // Rounds 0 and 1 kill 10-150 ms after the start (the process's start-up included: a whole
  // run of the beam takes well under 0.5 s on an idle machine), so also before a run is
  // recorded; rounds 2-4 0-60 ms after the run has recorded itself, so a loaded machine (a
  // sanitizer build beside other work) still interrupts recorded runs.
  std::uniform_int_distribution<int> delay_ms(10, 150), after_row_ms(0, 60);
  int kills = 0, finished_early = 0;
  for (int round = 0; round < 5; ++round) {
    const std::size_t runs_before = expand_runs(state);
    const pid_t pid = start_stage(HAPSTATE_EXPAND_EXE, expand_args(state, 1), dir_);
    if (round < 2) {
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    } else {
      wait_for_run_row(state, runs_before, pid);
      std::this_thread::sleep_for(std::chrono::milliseconds(after_row_ms(rng)));
    }
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

  expect_same_catalogue(reference, state);
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
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

// Until a later run resumes, hapstate-inspect tells a killed run from a live one by the state
// directory's lock: the catalogue still says "running", the summary says "interrupted".
TEST_F(Crash, KilledRunIsReportedInterrupted) {
  const fs::path state = dir_ / "state";
  if (!expand_and_signal({SIGKILL})) GTEST_SKIP() << "the expansion ended before the signal";
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    ASSERT_EQ(cat.read_stage_runs("expand").back().outcome, StageOutcome::kRunning);
  }
  const InspectOutput summary = inspect_summary(StateDir{state});
  EXPECT_NE(summary.text.find("expand: 1 runs, last #3 interrupted: the process ended before "
                              "finishing"),
            std::string::npos)
      << summary.text;
  EXPECT_EQ(summary.text.find("running"), std::string::npos) << summary.text;
  EXPECT_NE(summary.json.find("\"outcome\": \"interrupted\""), std::string::npos);
}

// Ctrl-C stops at a batch boundary: exit 130, the message says how to resume, the run is
// recorded as partial, and the next run says it resumes and completes.
TEST_F(Crash, CtrlCStopsCleanlyAndTheNextRunResumes) {
  const fs::path state = dir_ / "state";
  const std::optional<StageResult> stopped = expand_and_signal({SIGINT});
  if (!stopped) GTEST_SKIP() << "the expansion ended before the signal";
  const StageResult& r = *stopped;
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("stopped; run the same command again to resume"), std::string::npos)
      << r.err;
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    const StageRun run = cat.read_stage_runs("expand").back();
    EXPECT_EQ(run.outcome, StageOutcome::kPartial);
    EXPECT_NE(run.message.find("stopped (Ctrl-C or SIGTERM"), std::string::npos) << run.message;
  }
  const StageResult resumed = run_stage(
      HAPSTATE_EXPAND_EXE, {"--state", state.string(), "--threads", "1", "--batch", "8"}, dir_);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("resuming: "), std::string::npos) << resumed.err;
  EXPECT_NE(resumed.out.find("complete"), std::string::npos) << resumed.out;
}

// A second Ctrl-C ends the process at once (exit 130, with a message); the directory stays
// consistent and the next run completes.
TEST_F(Crash, SecondCtrlCStopsAtOnce) {
  const fs::path state = dir_ / "state";
  const std::optional<StageResult> stopped = expand_and_signal({SIGINT, SIGINT});
  if (!stopped) GTEST_SKIP() << "the expansion ended before the signal";
  const StageResult& r = *stopped;
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_TRUE(r.err.find("stopped at once") != std::string::npos ||
              r.err.find("stopped; run the same command again") != std::string::npos)
      << r.err;
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.integrity_check(), "ok");
  }
  const StageResult resumed = expand_stage(state, 1, dir_);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("complete"), std::string::npos) << resumed.out;
}

TEST_F(Crash, ChunkedRunsWithLimitsEqualOneRun) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 1, dir_);
  ASSERT_EQ(import_stage(state, kBeamScene, dir_).exit_code, 0);
  ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
  // A time limit ends the run cleanly at a batch boundary too: 1 ms, so it stops at its first
  // boundary, before the first batch, however fast the machine (a whole run of the beam can take
  // under 0.2 s); the --max-transitions runs below stop after committed work.
  const StageResult timed = expand_stage(state, 2, dir_, {"--max-seconds", "0.001"});
  ASSERT_EQ(timed.exit_code, 0) << timed.err;
  EXPECT_NE(timed.out.find("partial"), std::string::npos) << timed.out;
  int partial = 1;
  for (int round = 0; round < 100; ++round) {
    const StageResult r = expand_stage(state, 2, dir_, {"--max-transitions", "50"});
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
