// Damaged or foreign state directories: each gives a specific error (exit 2) and changes
// nothing.
#include "beam_state.h"

#include "catalogue/catalogue.h"

#include <sqlite3.h>

#include <chrono>
#include <thread>

namespace hapstate::test_util {
namespace {

// One expanded beam per test program; each test breaks a copy of it.
class BadState : public StageTest {
 protected:
  static void SetUpTestSuite() {
    root_ = new fs::path(fs::temp_directory_path() /
                         ("hapstate_bad_state_test_" + std::to_string(::getpid())));
    fs::remove_all(*root_);
    fs::create_directories(*root_);
    // Stop early so that the directory still has work to do (and segments to resume from).
    const fs::path state = *root_ / "reference";
    ASSERT_EQ(import_stage(state, kBeamScene, *root_).exit_code, 0);
    ASSERT_EQ(grid_stage(state, *root_).exit_code, 0);
    const StageResult e = expand_stage(state, 2, *root_, {"--max-transitions", "200"});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    ASSERT_NE(e.out.find("partial"), std::string::npos) << e.out;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*root_);
    delete root_;
  }
  fs::path copy_of_reference() {
    const fs::path to = dir_ / "state";
    fs::copy(*root_ / "reference", to, fs::copy_options::recursive);
    return to;
  }
  static fs::path* root_;
};
fs::path* BadState::root_ = nullptr;

// Runs every stage on the damaged `state` and expects exit 2 with `message` from each stage
// that reads what is damaged, and no change to any file.
void expect_refused(const fs::path& state, const fs::path& logs, const std::string& message,
                    bool grid_too) {
  const auto before = file_tree(state);
  const StageResult e = expand_stage(state, 2, logs);
  EXPECT_EQ(e.exit_code, 2) << e.err;
  EXPECT_NE(e.err.find(message), std::string::npos) << e.err;
  if (grid_too) {
    const StageResult g = grid_stage(state, logs);
    EXPECT_EQ(g.exit_code, 2) << g.err;
    EXPECT_NE(g.err.find(message), std::string::npos) << g.err;
  }
  EXPECT_TRUE(file_tree(state) == before) << "the state directory changed";
}

TEST_F(BadState, TruncatedSegment) {
  const fs::path state = copy_of_reference();
  const fs::path segment = state / "blobs" / "seg-000002.h5";
  ASSERT_TRUE(fs::exists(segment));
  fs::resize_file(segment, fs::file_size(segment) / 2);
  expect_refused(state, dir_, "seg-000002.h5", false);
}

TEST_F(BadState, MissingSegment) {
  const fs::path state = copy_of_reference();
  fs::remove(state / "blobs" / "seg-000003.h5");
  expect_refused(state, dir_, "seg-000003.h5", false);
}

TEST_F(BadState, MissingProblemSegment) {
  const fs::path state = copy_of_reference();
  fs::remove(state / "problem" / "seg-000001.h5");
  expect_refused(state, dir_, "problem/seg-000001.h5", true);
}

TEST_F(BadState, CatalogueFromAFutureSchemaVersion) {
  const fs::path state = copy_of_reference();
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((state / "catalogue.sqlite").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  expect_refused(state, dir_, "upgrade hapstate", true);
  const auto before = file_tree(state);
  const StageResult i = import_stage(state, kBeamScene, dir_);
  EXPECT_EQ(i.exit_code, 2) << i.err;
  EXPECT_NE(i.err.find("upgrade hapstate"), std::string::npos) << i.err;
  EXPECT_TRUE(file_tree(state) == before);
}

TEST_F(BadState, StateDirectoryOfAnotherScene) {
  const fs::path state = copy_of_reference();
  const auto before = file_tree(state);
  const std::string softer =
      beam_variant(dir_, "softer.toml", {{"young = 5000.0", "young = 4000.0"}});
  const StageResult i = import_stage(state, softer, dir_);
  EXPECT_EQ(i.exit_code, 2) << i.err;
  EXPECT_NE(i.err.find("was built from another scene; changed: the material"), std::string::npos)
      << i.err;
  EXPECT_NE(i.err.find("--fresh"), std::string::npos) << i.err;
  EXPECT_TRUE(file_tree(state) == before);

  const std::string other_fixed = beam_variant(
      dir_, "fixed.toml", {{"point = [0.0, 0.0, 0.0], normal", "point = [0.5, 0.0, 0.0], normal"}});
  const StageResult j = import_stage(state, other_fixed, dir_);
  EXPECT_EQ(j.exit_code, 2) << j.err;
  EXPECT_NE(j.err.find("the mesh geometry, the fixed/grabbed nodes or the loads"),
            std::string::npos)
      << j.err;
  const std::string smaller = beam_variant(
      dir_, "smaller.toml",
      {{"box = [[3.8, 0.4, 0.9], [4.2, 0.6, 1.1]]", "box = [[3.9, 0.4, 0.9], [4.2, 0.6, 1.1]]"}});
  const StageResult k = import_stage(state, smaller, dir_);
  EXPECT_EQ(k.exit_code, 2) << k.err;
  EXPECT_NE(k.err.find("the workspace may only be enlarged"), std::string::npos) << k.err;
  EXPECT_TRUE(file_tree(state) == before);

  // A bad scene given with --fresh deletes nothing.
  const std::string broken =
      beam_variant(dir_, "broken.toml", {{"young = 5000.0", "young = -1.0"}});
  const StageResult b = import_stage(state, broken, dir_, {"--fresh"});
  EXPECT_EQ(b.exit_code, 2) << b.err;
  EXPECT_TRUE(file_tree(state) == before);

  // --fresh starts over.
  const StageResult f = import_stage(state, softer, dir_, {"--fresh"});
  EXPECT_EQ(f.exit_code, 0) << f.err;
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.num_configurations(), 0);
  EXPECT_EQ(cat.num_checkpoints(), 0);
  EXPECT_FALSE(fs::exists(state / "blobs" / "seg-000001.h5"));
}

TEST_F(BadState, OneStageAtATime) {
  const fs::path state = copy_of_reference();
  const fs::path logs = dir_ / "first";
  fs::create_directories(logs);
  const pid_t first = start_stage(HAPSTATE_EXPAND_EXE, expand_args(state, 1), logs);
  // Wait until the first run works (its stage run is recorded while it holds the lock).
  bool running = false;
  for (int attempt = 0; attempt < 500 && !running; ++attempt) {
    {
      Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
      for (const StageRun& run : cat.read_stage_runs("expand"))
        running = running || run.outcome == StageOutcome::kRunning;
    }
    if (!running) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(running);
  // Meanwhile a second stage in the same directory is refused (exit 2) and changes nothing.
  const StageResult second = grid_stage(state, dir_);
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_NE(second.err.find("another hapstate stage is working in this state directory"),
            std::string::npos)
      << second.err;
  const bool refused = second.exit_code == 2;
  const StageResult r = wait_stage(first, logs);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(refused);
  // Afterwards the lock is free again.
  EXPECT_EQ(grid_stage(state, dir_).exit_code, 0);
}

TEST_F(BadState, NotAStateDirectory) {
  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  const StageResult g = grid_stage(empty, dir_);
  EXPECT_EQ(g.exit_code, 2);
  EXPECT_NE(g.err.find("run hapstate-import first"), std::string::npos) << g.err;
  const StageResult e = expand_stage(empty, 1, dir_);
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("run hapstate-import first"), std::string::npos) << e.err;
  EXPECT_TRUE(fs::is_empty(empty));
}

}  // namespace
}  // namespace hapstate::test_util
