// hapstate-expand under mpirun (docs/distributed.md): the catalogue equals a one-thread run's
// whatever the ranks and threads per rank, SIGKILL of mpirun at random moments then a resume
// gives it too, and --max-seconds stops cleanly. Ranks are oversubscribed on small machines.
#include "beam_state.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

namespace hapstate::test_util {
namespace {

const std::string kLiverScene = HAPSTATE_SOURCE_DIR "/pipelines/liver/scene.toml";
const std::string kLiverContactScene = HAPSTATE_SOURCE_DIR "/pipelines/liver-contact/scene.toml";

class Mpi : public StageTest {
 protected:
  void SetUp() override {
    StageTest::SetUp();
    // OpenMPI refuses to start as root without these (CI containers run as root).
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }

  // mpirun -n ranks --oversubscribe hapstate-expand <expand_args(state, threads, extra)>
  static std::vector<std::string> mpirun_args(int ranks, const fs::path& state, int threads,
                                              std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"-n", std::to_string(ranks), "--oversubscribe"};
    // Sanitized build (scripts/sanitize.sh): OpenMPI's run-time components keep allocations
    // that LeakSanitizer reports from modules already unloaded (no library name to suppress),
    // so the ranks run without leak detection; memory errors and undefined behaviour stay fatal.
    if (const char* asan = std::getenv("ASAN_OPTIONS"))
      for (const std::string& a :
           {std::string("-x"), "ASAN_OPTIONS=" + std::string(asan) + ":detect_leaks=0"})
        args.push_back(a);
    args.push_back(HAPSTATE_EXPAND_EXE);
    for (const std::string& a : expand_args(state, threads, std::move(extra))) args.push_back(a);
    return args;
  }

  StageResult mpi_expand(int ranks, const fs::path& state, int threads,
                         std::vector<std::string> extra = {}) {
    return run_stage(HAPSTATE_MPIEXEC, mpirun_args(ranks, state, threads, std::move(extra)), dir_);
  }

  void import_and_grid(const fs::path& state, const std::string& scene) {
    ASSERT_EQ(import_stage(state, scene, dir_).exit_code, 0);
    ASSERT_EQ(grid_stage(state, dir_).exit_code, 0);
  }

  // The pids whose parent is `parent` (from /proc).
  static std::vector<pid_t> children_of(pid_t parent) {
    std::vector<pid_t> out;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::ifstream stat(e.path() / "stat");
      std::string line;
      if (!std::getline(stat, line)) continue;
      // pid (comm) state ppid ...: comm may hold spaces, so read after the last ')'.
      std::istringstream rest(line.substr(line.rfind(')') + 2));
      char state = 0;
      pid_t ppid = 0;
      rest >> state >> ppid;
      if (ppid == parent && state != 'Z') out.push_back(static_cast<pid_t>(std::stoi(name)));
    }
    return out;
  }

  // How many processes have `path` among their arguments.
  static int processes_naming(const fs::path& path) {
    int count = 0;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::ifstream file(e.path() / "cmdline");
      std::string arg;
      while (std::getline(file, arg, '\0'))
        if (arg == path.string()) {
          ++count;
          break;
        }
    }
    return count;
  }

  static std::string run_name(int ranks, int threads) {
    std::string name = "n";
    name += std::to_string(ranks);
    name += "t";
    name += std::to_string(threads);
    return name;
  }
};

TEST_F(Mpi, RanksAndThreadsDoNotChangeTheBeamCatalogue) {
  const fs::path reference = dir_ / "reference";
  build_beam(reference, kBeamScene, 1, dir_);
  for (const auto& [ranks, threads] : {std::pair{3, 1}, std::pair{4, 2}}) {
    const fs::path state = dir_ / run_name(ranks, threads);
    import_and_grid(state, kBeamScene);
    const StageResult r = mpi_expand(ranks, state, threads, {"--timings"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The per-rank report: every worker solved some of the transitions.
    EXPECT_NE(r.out.find("MPI: " + std::to_string(ranks - 1) + " worker ranks x " +
                         std::to_string(threads) + " threads"),
              std::string::npos)
        << r.out;
    for (int rank = 1; rank < ranks; ++rank)
      EXPECT_NE(r.out.find("rank " + std::to_string(rank) + ": "), std::string::npos) << r.out;
    expect_same_catalogue(reference, state);
    // The stage run records how the work was distributed.
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_NE(
        cat.read_stage_runs("expand").back().parameters.find("ranks=" + std::to_string(ranks)),
        std::string::npos);
  }
}

// The whole liver expansion (344 configurations, 8 944 transitions) under 3 ranks of 2 threads
// against one thread (the beam above covers more combinations; a liver expansion takes about a
// minute here).
TEST_F(Mpi, RanksAndThreadsDoNotChangeTheLiverCatalogue) {
  const fs::path reference = dir_ / "reference";
  import_and_grid(reference, kLiverScene);
  ASSERT_EQ(expand_stage(reference, 1, dir_).exit_code, 0);
  const fs::path state = dir_ / run_name(3, 2);
  import_and_grid(state, kLiverScene);
  const StageResult r = mpi_expand(3, state, 2);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("complete"), std::string::npos) << r.out;
  expect_same_catalogue(reference, state);
}

// A sphere touching the liver (frictionless): the contact multipliers travel with the source
// vectors and come back with the results.
TEST_F(Mpi, ContactProbeCatalogueIsTheSame) {
  const std::vector<std::string> limit{"--max-transitions", "320"};
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  import_and_grid(reference, kLiverContactScene);
  ASSERT_EQ(expand_stage(reference, 1, dir_, limit).exit_code, 0);
  import_and_grid(state, kLiverContactScene);
  const StageResult r = mpi_expand(3, state, 1, limit);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_same_catalogue(reference, state);
}

TEST_F(Mpi, KilledMpirunResumesToTheSameCatalogue) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 1, dir_);
  import_and_grid(state, kBeamScene);
  std::mt19937 rng(20261123);
  // mpirun's start-up takes a few hundred ms; the whole run about a second.
  std::uniform_int_distribution<int> delay_ms(300, 1200);
  int kills = 0;
  for (int round = 0; round < 4; ++round) {
    const pid_t pid = start_stage(HAPSTATE_MPIEXEC, mpirun_args(3, state, 1), dir_);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    if (::kill(pid, SIGKILL) == 0) ++kills;
    wait_stage(pid, dir_);
    // The ranks die with their launcher (none is left holding the state directory).
    int left = 0;
    for (int tries = 0; tries < 100 && (left = processes_naming(state)) > 0; ++tries)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(left, 0) << "ranks still running 2 s after mpirun was killed";
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.integrity_check(), "ok");
  }
  EXPECT_GE(kills, 1);
  const StageResult last = mpi_expand(3, state, 1);
  ASSERT_EQ(last.exit_code, 0) << last.err;
  expect_same_catalogue(reference, state);
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  for (const StageRun& run : cat.read_stage_runs("expand"))
    EXPECT_NE(run.outcome, StageOutcome::kRunning);
}

// A worker rank killed: MPI ends the job (mpirun reports the rank), the catalogue is as after
// any crash, and the next run resumes to the same result.
TEST_F(Mpi, KilledWorkerRankEndsTheJobAndTheRunResumes) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 1, dir_);
  import_and_grid(state, kBeamScene);
  const pid_t mpirun = start_stage(HAPSTATE_MPIEXEC, mpirun_args(3, state, 1), dir_);
  // The ranks are mpirun's children; the highest pid started last (a worker or rank 0: either
  // ends the job). Wait until all three exist.
  std::vector<pid_t> ranks;
  for (int tries = 0; tries < 400 && ranks.size() < 3; ++tries) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ranks = children_of(mpirun);
  }
  ASSERT_EQ(ranks.size(), 3u);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  ASSERT_EQ(::kill(*std::max_element(ranks.begin(), ranks.end()), SIGKILL), 0);
  const StageResult killed = wait_stage(mpirun, dir_);
  EXPECT_NE(killed.exit_code, 0);
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.integrity_check(), "ok");
  }
  const StageResult resumed = mpi_expand(3, state, 1);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_catalogue(reference, state);
}

TEST_F(Mpi, MaxSecondsStopsCleanlyAndResumes) {
  const fs::path reference = dir_ / "reference", state = dir_ / "state";
  build_beam(reference, kBeamScene, 1, dir_);
  import_and_grid(state, kBeamScene);
  // A limit shorter than the run: it stops at a batch boundary with exit 0, outcome partial.
  const StageResult partial = mpi_expand(3, state, 1, {"--max-seconds", "0.05"});
  ASSERT_EQ(partial.exit_code, 0) << partial.err;
  EXPECT_NE(partial.out.find("partial"), std::string::npos) << partial.out;
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.read_stage_runs("expand").back().outcome, StageOutcome::kPartial);
    EXPECT_LT(cat.num_transitions(), snapshot(reference).transitions.size());
  }
  const StageResult rest = mpi_expand(4, state, 2);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  expect_same_catalogue(reference, state);
}

// A bad state directory under mpirun: rank 0's clear error and exit code, every rank ends.
TEST_F(Mpi, BadStateDirectoryEndsEveryRankWithTheError) {
  const StageResult r = mpi_expand(3, dir_ / "missing", 1);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace hapstate::test_util
