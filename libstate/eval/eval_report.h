// hapstate-eval's outputs: the per-step CSV, the accuracy table, the plot (Fig. 2 style).
#pragma once

#include "eval/evaluation.h"

#include <filesystem>
#include <string>

namespace hapstate {

// step,x,y,z,fx*,fy*,fz*,solved, then per scheme <name>_fx,_fy,_fz,_force_error,
// _deformation_error_all,_deformation_error_surface.
void write_eval_csv(const EvalResult& result, const std::filesystem::path& file);

// The accuracy table: what the errors mean, per scheme max / mean force error and deformation
// errors, a verdict against the paper's bounds, failures and the mean precise solve time.
// (Query cost is not here: one timed call per step says nothing; hapstate-play and
// bench/playback_bench measure it.)
std::string eval_table(const EvalResult& result);

// Renders the CSV as a PNG with matplotlib (python3 from Debian's python3-matplotlib): relative
// force and deformation error per step, one line per scheme. Throws InputError with Python's
// message if it fails.
void plot_eval(const std::filesystem::path& csv, const std::filesystem::path& png,
               const std::string& title);

}  // namespace hapstate
