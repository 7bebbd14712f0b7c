// Helpers for tests that run the real stage executables on a state directory: running a
// stage (fork/exec, output captured), snapshots of a catalogue for comparisons.
#pragma once

#include "../common/scene_variant.h"
#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hapstate::test_util {

namespace fs = std::filesystem;

struct StageResult {
  int exit_code = -1;  // -1: killed by a signal
  std::string out, err;
};

// Starts `exe args...` with stdout/stderr into files in `log_dir`; returns the pid.
inline pid_t start_stage(const std::string& exe, const std::vector<std::string>& args,
                         const fs::path& log_dir) {
  const std::string out = (log_dir / "stdout.txt").string(),
                    err = (log_dir / "stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fo = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fe = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fo, 1);
    ::dup2(fe, 2);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

inline StageResult wait_stage(pid_t pid, const fs::path& log_dir) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  StageResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(log_dir / "stdout.txt");
  r.err = slurp(log_dir / "stderr.txt");
  return r;
}

inline StageResult run_stage(const std::string& exe, const std::vector<std::string>& args,
                             const fs::path& log_dir) {
  return wait_stage(start_stage(exe, args, log_dir), log_dir);
}

// Everything a catalogue decided, for comparisons (stage runs and wall times excluded: they
// differ between runs by nature).
struct Snapshot {
  std::vector<Checkpoint> checkpoints;
  std::vector<Configuration> configurations;
  std::vector<Transition> transitions;  // wall_ms zeroed
  std::vector<std::string> segment_files;
};

inline Snapshot snapshot(const fs::path& state) {
  Snapshot s;
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  s.checkpoints = cat.read_all_checkpoints();
  s.configurations = cat.read_all_configurations();
  s.transitions = cat.read_all_transitions();
  for (auto& t : s.transitions) t.wall_ms = 0;
  if (fs::exists(state / "blobs"))
    for (const auto& e : fs::directory_iterator(state / "blobs"))
      s.segment_files.push_back(e.path().filename().string());
  std::sort(s.segment_files.begin(), s.segment_files.end());
  return s;
}

// The largest |a - b| over the u, t and h vectors of corresponding configurations (which must
// have the same blob layout), relative to the largest |u| / |h|.
inline double max_vector_difference(const fs::path& a, const fs::path& b,
                                    const std::vector<Configuration>& configs) {
  BlobStore sa(a / "blobs"), sb(b / "blobs");
  double worst = 0;
  for (const Configuration& c : configs) {
    if (!c.blob) continue;
    for (const char* v : {"/u", "/t", "/h"}) {
      const auto x = sa.read(c.blob->segment, c.blob->name + v);
      const auto y = sb.read(c.blob->segment, c.blob->name + v);
      EXPECT_EQ(x.size(), y.size());
      double scale = 1e-300;
      for (double e : x) scale = std::max(scale, std::abs(e));
      for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k)
        worst = std::max(worst, std::abs(x[k] - y[k]) / scale);
    }
  }
  return worst;
}

// Exact comparison of everything but the vectors (and wall times). With `cost_may_differ`
// (two solver algorithms), the solver's work (sub-steps, iterations, factorisations) is not
// compared, forces, stiffnesses and summaries agree to `relative` of their scale, and a
// transition may reach another level of the same check-point (a result within the level
// tolerance of two levels picks the nearer: a near tie that the solver tolerance can flip);
// returns how many did.
// `stiffness_relative` (> 0): the stiffnesses may differ by that fraction of the configuration's
// largest entry instead (contact: docs/contact.md, where a barely touched triangle may be held
// active in one solve and not in another within the solver's tolerance).
inline int expect_same_decisions(const Snapshot& a, const Snapshot& b, bool cost_may_differ = false,
                                 double relative = 1e-12, double stiffness_relative = 0.0) {
  int level_ties = 0;
  std::map<std::int64_t, std::int64_t> checkpoint_of;
  for (const Configuration& c : a.configurations)
    checkpoint_of[c.id.value()] = c.checkpoint.value();
  EXPECT_EQ(a.checkpoints, b.checkpoints);
  EXPECT_EQ(a.configurations.size(), b.configurations.size());
  if (a.configurations.size() != b.configurations.size()) return -1;
  for (std::size_t k = 0; k < a.configurations.size(); ++k) {
    const Configuration& x = a.configurations[k];
    const Configuration& y = b.configurations[k];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.checkpoint, y.checkpoint) << "configuration " << x.id.value();
    EXPECT_EQ(x.level, y.level) << "configuration " << x.id.value();
    EXPECT_EQ(x.wave, y.wave) << "configuration " << x.id.value();
    EXPECT_EQ(x.expandable, y.expandable) << "configuration " << x.id.value();
    EXPECT_EQ(x.status, y.status) << "configuration " << x.id.value();
    EXPECT_EQ(x.blob, y.blob) << "configuration " << x.id.value();
    const double force_scale =
        std::max({1e-3, std::abs(x.force[0]), std::abs(x.force[1]), std::abs(x.force[2])});
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(x.force[c], y.force[c], relative * force_scale)
          << "configuration " << x.id.value();
    double stiffness_scale = 0.0;
    for (double k : x.stiffness) stiffness_scale = std::max(stiffness_scale, std::abs(k));
    for (int c = 0; c < 9; ++c)
      EXPECT_NEAR(x.stiffness[c], y.stiffness[c],
                  stiffness_relative > 0
                      ? stiffness_relative * stiffness_scale + 1e-12
                      : std::max(1e-9, relative) * (1 + std::abs(x.stiffness[c])))
          << "configuration " << x.id.value();
    EXPECT_EQ(x.summary.size(), y.summary.size());
    if (x.summary.size() != y.summary.size()) return -1;
    double summary_scale = 1e-12;
    for (double v : x.summary) summary_scale = std::max(summary_scale, std::abs(v));
    for (std::size_t c = 0; c < x.summary.size(); ++c)
      EXPECT_NEAR(x.summary[c], y.summary[c], std::max(1e-12, relative * summary_scale));
  }
  EXPECT_EQ(a.transitions.size(), b.transitions.size());
  if (a.transitions.size() != b.transitions.size()) return -1;
  std::size_t midpoint_differences = 0, onset_differences = 0;
  for (std::size_t k = 0; k < a.transitions.size(); ++k) {
    const Transition& x = a.transitions[k];
    const Transition& y = b.transitions[k];
    EXPECT_EQ(x.source, y.source);
    EXPECT_EQ(x.direction, y.direction);
    EXPECT_EQ(x.outcome, y.outcome)
        << "transition " << x.source.value() << "/" << x.direction.index();
    if (cost_may_differ && x.target != y.target && x.target.valid() && y.target.valid() &&
        checkpoint_of[x.target.value()] == checkpoint_of[y.target.value()]) {
      ++level_ties;
    } else {
      EXPECT_EQ(x.target, y.target)
          << "transition " << x.source.value() << "/" << x.direction.index();
    }
    if (!cost_may_differ) {
      EXPECT_EQ(x.substeps, y.substeps);
      EXPECT_EQ(x.newton_iterations, y.newton_iterations);
      EXPECT_EQ(x.factorisations, y.factorisations);
    }
    EXPECT_EQ(x.failure_reason, y.failure_reason);
    // Two algorithms may differ in whether the first half of a move converged (a half that fails
    // is solved whole and records no midpoint): counted, at most 0.1 % of the transitions.
    if (cost_may_differ && x.midpoint_force.has_value() != y.midpoint_force.has_value()) {
      ++midpoint_differences;
    } else {
      EXPECT_EQ(x.midpoint_force.has_value(), y.midpoint_force.has_value())
          << "transition " << x.source.value() << "/" << x.direction.index();
    }
    if (x.midpoint_force && y.midpoint_force) {
      const auto& m = *x.midpoint_force;
      const double scale = std::max({1e-3, std::abs(m[0]), std::abs(m[1]), std::abs(m[2])});
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(m[c], (*y.midpoint_force)[c], std::max(1e-12, relative) * scale)
            << "transition " << x.source.value() << "/" << x.direction.index();
      EXPECT_EQ(x.midpoint_stiffness.has_value(), y.midpoint_stiffness.has_value());
    }
    if (x.midpoint_force && y.midpoint_force && x.midpoint_stiffness && y.midpoint_stiffness) {
      const auto& k = *x.midpoint_stiffness;
      auto untouched = [](const std::array<double, 9>& m) {
        return std::all_of(m.begin(), m.end(), [](double v) { return v == 0.0; });
      };
      // A sphere that grazes the body half-way may touch it in one state and not in the other
      // (the force differs by the tolerance, the stiffness jumps at the contact onset): counted.
      if (cost_may_differ && untouched(k) != untouched(*y.midpoint_stiffness)) {
        ++onset_differences;
        continue;
      }
      // As the configurations' stiffness.
      double scale = 0.0;
      for (double v : k) scale = std::max(scale, std::abs(v));
      for (int e = 0; e < 9; ++e)
        EXPECT_NEAR(k[e], (*y.midpoint_stiffness)[e],
                    stiffness_relative > 0 ? stiffness_relative * scale + 1e-12
                                           : std::max(1e-9, relative) * (1 + std::abs(k[e])))
            << "transition " << x.source.value() << "/" << x.direction.index();
    }
  }
  EXPECT_LE(midpoint_differences, a.transitions.size() / 1000) << "midpoints recorded by one only";
  EXPECT_LE(onset_differences, a.transitions.size() / 100) << "midpoints touching in one only";
  if (onset_differences > 0)
    std::printf("[ info ] %zu midpoints touch the body in one state only\n", onset_differences);
  if (midpoint_differences > 0)
    std::printf("[ info ] %zu transitions record a midpoint force in one state only\n",
                midpoint_differences);
  EXPECT_EQ(a.segment_files, b.segment_files);
  return level_ties;
}

// A fresh directory per test, removed when the test passed.
// The state directory `state` holds the same decisions as `reference`, vectors within 1e-12
// of their scale, an intact catalogue and no unreferenced segment (after a crash, a resume,
// other threads or ranks).
inline void expect_same_catalogue(const fs::path& reference, const fs::path& state) {
  const Snapshot a = snapshot(reference), b = snapshot(state);
  expect_same_decisions(a, b);
  EXPECT_LE(max_vector_difference(reference, state, a.configurations), 1e-12);
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.integrity_check(), "ok");
  BlobStore blobs(state / "blobs");
  EXPECT_TRUE(blobs.unreferenced_segments(cat.referenced_segments()).empty());
}

class StageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("hapstate_stage_test_" + std::to_string(::getpid()) + "_" +
                                        info->name() + "_" + std::to_string(counter++));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

}  // namespace hapstate::test_util
