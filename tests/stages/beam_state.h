// The beam scene (pipelines/beam/) run through the stages: scene variants and a reference
// state directory built once per test program.
#pragma once

#include "stage_runner.h"

#include <utility>

namespace hapstate::test_util {

inline StageResult import_stage(const fs::path& state, const std::string& scene,
                                const fs::path& log_dir, std::vector<std::string> extra = {}) {
  std::vector<std::string> args{scene, "--state", state.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_stage(HAPSTATE_IMPORT_EXE, args, log_dir);
}

inline StageResult grid_stage(const fs::path& state, const fs::path& log_dir) {
  return run_stage(HAPSTATE_GRID_EXE, {"--state", state.string()}, log_dir);
}

inline std::vector<std::string> expand_args(const fs::path& state, int threads,
                                            std::vector<std::string> extra = {}) {
  std::vector<std::string> args{
      "--state", state.string(), "--threads", std::to_string(threads), "--batch", "8", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

inline StageResult expand_stage(const fs::path& state, int threads, const fs::path& log_dir,
                                std::vector<std::string> extra = {}) {
  return run_stage(HAPSTATE_EXPAND_EXE, expand_args(state, threads, std::move(extra)), log_dir);
}

// import + grid + expand of the beam into `state`; asserts each stage succeeded.
inline void build_beam(const fs::path& state, const std::string& scene, int threads,
                       const fs::path& log_dir) {
  const StageResult i = import_stage(state, scene, log_dir);
  ASSERT_EQ(i.exit_code, 0) << i.err;
  const StageResult g = grid_stage(state, log_dir);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const StageResult e = expand_stage(state, threads, log_dir);
  ASSERT_EQ(e.exit_code, 0) << e.err;
}

// Relative path -> bytes of every file under `root` except SQLite's -wal/-shm.
inline std::map<std::string, std::string> file_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (name.ends_with("-wal") || name.ends_with("-shm")) continue;
    files[fs::relative(e.path(), root).string()] = slurp(e.path());
  }
  return files;
}

}  // namespace hapstate::test_util
