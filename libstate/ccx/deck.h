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
// t_k = (p_k - problem.probe_rest) * unit metres, the fixed DOFs to 0. With gravity
// (problem.loads) a first step finds the loaded rest state (*DENSITY, *DLOAD GRAV, kept by the
// later steps), with the probe nodes free when the path is empty, else held at their rest
// displacement (problem.rest_m: ccx ramps a new prescribed displacement from zero), and the
// probe DOFs are then prescribed to that displacement + t_k: path point k ends at time k + 1
// (ccx_first_point_time; an empty path is allowed then: the rest step alone). Supports
// (loads.spring) are SPRING1 elements, one per DOF. Node ids are ours + 1, coordinates in
// metres, so ccx forces are in N. Throws InputError for an empty path (without gravity), an
// inconsistent problem (DOF roles vs mesh) or material constants ccx cannot represent.
void write_ccx_deck(const Problem& problem, const std::vector<Eigen::Vector3d>& probe_path,
                    const std::filesystem::path& dir, const CcxDeckOptions& options = {});

// The step time at whose end the deck's first path point is printed: 2 after a rest step
// (gravity), else 1; point k at time k - 1 + ccx_first_point_time.
inline int ccx_first_point_time(const Problem& problem) {
  return problem.loads.has_force() ? 2 : 1;
}

// The body force on the probe's DOFs summed per component [N] (zero without gravity). ccx's RF
// at a prescribed node is its internal force alone, while hapstate's felt force also counts the
// node's own weight (it is zero at the rest state): felt = -(sum of RF) + this.
inline Eigen::Vector3d probe_body_force(const Problem& problem) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  if (!problem.loads.has_force()) return sum;
  for (int node : problem.constraints.probe_nodes)
    for (int c = 0; c < 3; ++c)
      if (problem.constraints.role[3 * node + c] == DofRole::kProbe)
        sum[c] += problem.loads.force[3 * node + c];
  return sum;
}

// The *MATERIAL body of the deck for `c` (the law's keyword card and its data line).
// Throws InputError for constants outside the law's domain (mu <= 0, nu outside (-1, 0.5),
// c10 <= 0, d1 <= 0, ...).
std::string ccx_material_cards(const MaterialConstants& c);

// True when the law needs NLGEOM (every law but `linear`).
bool ccx_needs_nlgeom(Law law);

}  // namespace hapstate
