// hapstate-eval: the paper's experiment (§4, Fig. 2). A probe path is solved precisely (the
// path solver, step by step from rest) and played back by haptic cursors of each scheme; per
// step the relative force error |f - f*| / max_path |f*| and the relative deformation error
// ||u - u*|| / ||u*|| (all nodes when the playback file holds them, and surface nodes).
#pragma once

#include "hapstate/playback.h"
#include "io/probe_path.h"
#include "playback/scheme_name.h"
#include "problem/problem.h"

#include <Eigen/Core>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

struct EvalOptions {
  std::filesystem::path state;
  std::filesystem::path playback;   // "" = <state>/playback.bin
  std::filesystem::path path_file;  // a probe path CSV instead of the random path
  // The paper's experiment as the certificate runs it by default (certify.steps = 30): a path of
  // seed s is then the certificate's path of seed s, and its errors are among the certificate's.
  int steps = 30;
  std::uint64_t seed = 1;
  double step_length = 0;        // mesh units; 0 = half the smallest grid spacing
  std::FILE* progress = stderr;  // the precise solves' progress line (nullptr: none)
};

struct SchemeResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  double force_error = 0;             // |f - f*| / max over the path of |f*|
  double deformation_error_all = -1;  // ||u - u*|| / ||u*|| over all nodes (-1: not stored)
  double deformation_error_surface = 0;
};

struct EvalStep {
  Eigen::Vector3d probe = Eigen::Vector3d::Zero();  // mesh units
  Eigen::Vector3d exact_force = Eigen::Vector3d::Zero();
  bool solved = true;
  std::string failure;  // the solver's reason if !solved
  double solve_ms = 0;
  // Contact probe: in contact, less than one grid spacing of path travelled since the last
  // step off the body. u* is small there and the relative deformation error large, so the
  // deformation statistics leave these steps out (the CSV keeps them).
  bool contact_onset = false;
  std::vector<SchemeResult> schemes;  // one per EvalResult::schemes
};

struct EvalResult {
  std::filesystem::path playback;
  std::vector<Scheme> schemes{Scheme::kTrilinear, Scheme::kHermite};
  std::vector<EvalStep> steps;
  double max_exact_force = 0;  // N
  bool has_all_nodes = false;
  Eigen::Vector3d spacing = Eigen::Vector3d::Zero();
  std::string path_description;  // "random path: 20 steps of 0.25 mesh units, seed 1"
  int outside_grid = 0;          // steps outside the precomputed grid (playback extends)
};

// Steps whose precise solve failed.
inline int failed_steps(const EvalResult& r) {
  int n = 0;
  for (const EvalStep& s : r.steps) n += !s.solved;
  return n;
}

// Runs the experiment. Throws InputError naming the file if the state directory or the
// playback file is unusable or they do not belong together (different scene).
EvalResult run_eval(const EvalOptions& options);

// The experiment on one path, with the problem loaded and the playback file open (run_eval
// without the state directory: several may run at once on the same problem and file, each with
// its own solver and cursors). `progress`: the precise solves' progress line (nullptr: none).
EvalResult evaluate_path(const Problem& problem, const PlaybackFile& file, const ProbePath& path,
                         std::FILE* progress);

}  // namespace hapstate
