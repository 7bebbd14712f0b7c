// hapstate-eval's outputs: the per-step CSV, the accuracy table, the plot (Fig. 2 style).
#pragma once

#include "eval/evaluation.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

// step,x,y,z,fx*,fy*,fz*,solved, then per scheme <name>_fx,_fy,_fz,_force_error,
// _deformation_error_all,_deformation_error_surface.
void write_eval_csv(const EvalResult& result, const std::filesystem::path& file);

// The accuracy table: what the errors mean, per scheme max / mean force error and deformation
// errors, a verdict against the paper's bounds, failures and the mean precise solve time.
// (Query cost is not here: one timed call per step says nothing; hapstate-play and
// bench/playback_bench measure it.)
std::string eval_table(const EvalResult& result);

// One scheme's errors over a path's solved steps (fractions): force max and mean; deformation
// max and mean over all nodes and over the surface, leaving out the steps just past a first
// contact (EvalStep::contact_onset), whose largest deformation error is kept apart.
struct SchemeSummary {
  double force_max = 0, force_mean = 0;
  double deformation_all_max = 0, deformation_all_mean = 0;
  double deformation_surface_max = 0, deformation_surface_mean = 0;
  double onset_deformation_max = 0;
  // All nodes when the playback file holds them, else the surface.
  double deformation_max(const EvalResult& r) const {
    return r.has_all_nodes ? deformation_all_max : deformation_surface_max;
  }
};
SchemeSummary summarize(const EvalResult& result, std::size_t scheme);

// Many seeded paths (hapstate-eval --seeds): per scheme the median, 90th percentile and largest
// of the paths' largest force and deformation errors, and how many paths exceed the paper's
// bounds; `runs[k]` used seed first_seed + k.
std::string seeds_table(const std::vector<EvalResult>& runs, std::uint64_t first_seed);
// seed,max_exact_force, then per scheme <name>_force_error_max,<name>_deformation_error_max.
void write_seeds_csv(const std::vector<EvalResult>& runs, std::uint64_t first_seed,
                     const std::filesystem::path& file);

// Renders the CSV as a PNG with matplotlib (python3 from Debian's python3-matplotlib): relative
// force and deformation error per step, one line per scheme. Throws InputError with Python's
// message if it fails.
void plot_eval(const std::filesystem::path& csv, const std::filesystem::path& png,
               const std::string& title);

}  // namespace hapstate
