// A test suite over one state directory, built by the stage programs once per test program
// (in the derived suite's SetUpTestSuite) under a temporary root that is removed at the end.
#pragma once

#include "../stages/beam_state.h"

#include <gtest/gtest.h>

namespace hapstate::test_util {

class StateSuite : public ::testing::Test {
 protected:
  // Creates the root directory <tmp>/hapstate_<name>_<pid>; the state directory is root/state.
  static void make_root(const std::string& name) {
    root_ = new fs::path(fs::temp_directory_path() /
                         ("hapstate_" + name + "_" + std::to_string(::getpid())));
    fs::create_directories(*root_);
    state_ = new fs::path(*root_ / "state");
  }
  // hapstate-index --nodes all into state/playback.bin.
  static void index_all_nodes() {
    const StageResult r =
        run_stage(HAPSTATE_INDEX_EXE, {"--state", state_->string(), "--nodes", "all"}, *root_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*root_);
    delete root_;
    delete state_;
  }
  inline static fs::path* root_ = nullptr;
  inline static fs::path* state_ = nullptr;
};

}  // namespace hapstate::test_util
