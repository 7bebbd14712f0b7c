// Export of a probe-path problem as a CalculiX (ccx 2.20) input deck, for cross-checking our
// solver against an independent one. See docs/calculix.md for the mapping and sign conventions.
#pragma once

#include "problem/problem.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

// How ccx is asked to solve each path point. The defaults are tight enough that ccx's own
// convergence error stays far below its 7-digit output (see docs/calculix.md).
struct CcxDeckOptions {
  int increments_per_step = 4;         // fixed increments (*STATIC, DIRECT) per path point, >= 1
  bool allow_cutbacks = false;         // true: automatic incrementation, increment <= 1/n
  double residual_tolerance = 1e-9;    // *CONTROLS FIELD R_n = R_p: max residual / average force
  double correction_tolerance = 1e-9;  // *CONTROLS FIELD C_n: max correction / max increment
  int max_iterations = 40;             // *CONTROLS TIME INCREMENTATION I_C, per increment
  bool write_frd = false;              // also request *NODE FILE U, RF (problem.frd, for viewers)
};

// File names inside the deck directory.
inline constexpr const char* kCcxJobName = "problem";  // ccx -i problem
inline constexpr const char* kCcxDeckFile = "problem.inp";
inline constexpr const char* kCcxPathFile = "path.csv";       // x,y,z (mesh units), row k = step k
inline constexpr const char* kCcxMetaFile = "hapstate.json";  // what the .dat reader needs

// Writes DIR/problem.inp, DIR/path.csv and DIR/hapstate.json (creating DIR if needed).
// One ccx *STEP per point p_k of `probe_path` (mesh units): the probe DOFs are prescribed to
// t_k = (p_k - problem.probe_rest) * unit metres, the fixed DOFs to 0. Node ids are ours + 1,
// coordinates in metres, so ccx forces are in N. Throws InputError for an empty path, an
// inconsistent problem (DOF roles vs mesh) or material constants ccx cannot represent.
void write_ccx_deck(const Problem& problem, const std::vector<Eigen::Vector3d>& probe_path,
                    const std::filesystem::path& dir, const CcxDeckOptions& options = {});

// The *MATERIAL body of the deck for `c` (the law's keyword card and its data line).
// Throws InputError for constants outside the law's domain (mu <= 0, nu outside (-1, 0.5),
// c10 <= 0, d1 <= 0, ...).
std::string ccx_material_cards(const MaterialConstants& c);

// True when the law needs NLGEOM (every law but `linear`).
bool ccx_needs_nlgeom(Law law);

}  // namespace hapstate
