// The numerical stress suite (tools/hapstate-stress, docs/benchmarks.md "Numerical stress
// suite"): the precise path solver over a matrix of law x Poisson's ratio x load x step size x
// mesh quality x probe, each case classified as converged (with finite outputs) or failed with
// the solver's reason.
//
// The body: a bar [0, 2] x [0, 1] x [0, 1] (mesh units, unit = 1 cm), 8 x 4 x 4 cells of 6 tets
// (225 nodes, grid spacing h = 0.25), E = 10 kPa.
//   node / patch probe: xmin clamped; the centre node of the xmax face, or the whole xmax face,
//   grabbed (all components). Loads: stretch t = (+1, 0, 0) (50 % of the length), compress
//   t = (-0.6, 0, 0) (30 %), shear t = (0, +1, 0) (bending, half the length sideways).
//   contact probe: zmin clamped; a frictionless sphere of radius 0.5 starting 0.05 above the
//   middle of the top face. Loads: stretch = indent 0.45 (45 % of the height, the surface
//   stretches around the sphere), compress = indent 0.3, shear = indent 0.25 then slide +0.5
//   along x.
// The strain a case reached is measured, not assumed: the largest and smallest principal
// stretch of any tet (and the smallest det F) at the last converged state.
#pragma once

#include "eval/stress_mesh.h"
#include "material/material.h"
#include "problem/problem.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hapstate {

enum class StressProbe { kNode, kPatch, kContact };
enum class StressLoad { kStretch, kCompress, kShear };
// kGrid: moves of one grid spacing along the path; kWhole: each leg of the path in ONE move.
// kFine (the retry of a failed case only): moves of a quarter grid spacing.
enum class StressStep { kGrid, kWhole, kFine };
enum class StressMesh { kRegular, kSliver };

const char* stress_name(StressProbe p);
const char* stress_name(StressLoad l);
const char* stress_name(StressStep s);
const char* stress_name(StressMesh m);

struct StressCase {
  Law law = Law::kNeoHooke;
  double poisson = 0.3;
  StressLoad load = StressLoad::kStretch;
  StressStep step = StressStep::kGrid;
  StressMesh mesh = StressMesh::kRegular;
  StressProbe probe = StressProbe::kPatch;
  std::string id() const;  // "neohooke/nu0.3/stretch/grid/regular/patch"
};

// The matrices: `full` every combination of law {linear, stvk, neohooke, mooney} x nu {0.3,
// 0.45, 0.49, 0.499, 0.4999} x load x step {grid, whole} x mesh x probe (720 cases); `quick`
// the CI subset (stress_case.cc says which).
std::vector<StressCase> stress_matrix(bool full);

// Keeps the cases whose id() contains every comma-separated term of `filter` as a substring
// ("stvk,compress" keeps StVK compression cases). Empty: all.
std::vector<StressCase> filter_cases(const std::vector<StressCase>& cases,
                                     const std::string& filter);

struct StressOutcome {
  StressCase c;
  std::string status;   // "converged", "failed", "wall_cap", "nan" (a bug), "exception" (a bug)
  std::string failure;  // the solver's failure name (failure_name) or the status's reason
  std::string reason;   // the solver's reason, empty if converged
  int moves = 0, moves_done = 0;
  double reached = 0;  // fraction of the path's length reached (1 if converged)
  int iterations = 0, substeps = 0, cutbacks = 0, factorisations = 0;
  long long psd_fallbacks = 0;
  int split_moves = 0;  // moves that converged only split into pieces (MoveResult::split_pieces)
  double wall_ms = 0;
  double max_force = 0;  // N, over the converged moves
  StretchRange strain;   // at the last converged state
  double mesh_min_quality = 0;
  // A failed case run again with moves of a quarter grid spacing: "" (not run), "converged" or
  // "failed: <failure name>".
  std::string retry;
  bool bug() const {
    return status == "nan" || status == "exception" || (status == "failed" && reason.empty());
  }
};

// The problem of a case (mesh, material, constraints, probe) and its probe path: the targets of
// the legs (t, mesh units, relative to probe_rest), before splitting into moves.
Problem stress_problem(const StressCase& c);
std::vector<Eigen::Vector3d> stress_legs(const StressCase& c);

// Runs one case from rest: the legs split into moves by c.step, each move by PathSolver::move_to,
// stopping at the first failed move or once `wall_cap_s` seconds have passed (checked between
// moves; the solver's own iteration and cut-back caps bound a move). Never throws: an exception
// becomes status "exception". `retry`: run a failed case again with StressStep::kFine.
StressOutcome run_stress_case(const StressCase& c, double wall_cap_s, bool retry);

}  // namespace hapstate
