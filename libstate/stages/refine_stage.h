// The refine stage (hapstate run, after expand): the force and haptic stiffness at the
// quarter-spacing lattice points of every cell where the half-spacing data do not resolve the
// force (docs/state-space.md, "Refined cells").
#pragma once

#include "catalogue/records.h"
#include "statedir/stage_run.h"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

namespace hapstate {

// The default tolerance of a cell's estimated interpolation error, as a fraction of the largest
// force in the cell (grid.refine_tolerance in the scene overrides it).
constexpr double kDefaultRefineTolerance = 1e-3;

// Depth 3 refines the eighth cells of a flagged cell whose estimate from its eighth-spacing
// lattice exceeds this many times the tolerance times the cell's largest force. The estimate sees
// 0.15 to 0.25 of the error a force ramp much narrower than an eighth cell causes (the quintic
// through a run of three points bends less than the cubic pieces miss), so 5 x 10^-3 catches the
// ramps that cost more than about 2 to 3 % of the force. Measured on the liver touched at h = r
// (docs/contact.md, "Refined contact cells"): of its 43 cells' 22 016 eighth cells 5 095 are above
// 5 x 10^-3 and 2 145 above 10^-2 (runs across faces included; inside cells only, 9 630 were above
// 10^-3), each about 10 solves; the certificate's worst Hermite error 2.59 % at 10^-2, 1.34 % at
// 5 x 10^-3.
constexpr int kSixteenthToleranceFactor = 5;

// The default refinement depth (grid.refine_depth overrides it): for a contact sphere of
// `radius`, 3 where the largest grid `spacing` exceeds kDeeperRefineRatio times the radius, 2
// where it exceeds kDeepRefineRatio times it, else 1 (radius 0: the grab probe). The contact
// force's kinks err by about h / (8 r) of the force per cell; measured (docs/contact.md, "Refined
// contact cells"): depth 1 at h / r = 0.1 meets the accuracy bounds (Hermite 0.87 %, trilinear
// 1.79 %), at 0.2 not; depth 2 up to 0.4, at 1.0 not (Hermite 2.25 %); depth 3 at 1.0 (1.36 %).
constexpr double kDeepRefineRatio = 0.1;
constexpr double kDeeperRefineRatio = 0.4;
int default_refine_depth(double radius, double spacing);

// The largest spacing over the radius at which the default depth's contact playback was measured
// within Hermite 1.5 % and trilinear 3 % of the force (on liverSemiFine at 1.0, depth 3: Hermite
// 1.36 %, trilinear 1.61 %; at 1.7, depth 3: Hermite 4.47 %, trilinear 5.07 %: docs/scene.md,
// "Choosing the spacing for a contact probe").
constexpr double kMeasuredSpacingRatio = 1.0;
// For a contact sphere of `radius` with the largest grid `spacing` beyond kMeasuredSpacingRatio
// times it, a note saying so and what to do (the grid stage's line shows it); else "".
std::string contact_spacing_note(double radius, double spacing);

struct RefineOptions {
  std::filesystem::path state;
  int threads = 1;                  // worker threads, one PathSolver each
  std::optional<double> tolerance;  // relative, > 0; default: the scene's
  // 1: a flagged cell's quarter-spacing lattice; 2: also its eighth-spacing one; 3: also the
  // sixteenth-spacing points of its eighth cells above the tolerance. Default: the scene's
  // grid.refine_depth, else default_refine_depth.
  std::optional<int> depth;
  std::FILE* progress = stderr;  // progress line; nullptr: none

  // Throws InputError naming the first option out of range (run_refine calls it first).
  void check() const;
};

// outcome: kOk, kPartial (stopped), kUnchanged.
struct RefineReport : StageReport {
  double tolerance = 0;              // relative, as used
  int depth = 1;                     // as used
  long long cells = 0;               // cells with all 8 corners stored
  long long flagged = 0;             // of which above the tolerance
  long long refined_before = 0;      // flagged or not, refined (depth 1) by earlier runs
  long long refined = 0;             // cells refined (further) in this run, per depth pass
  long long eighth_flagged = 0;      // depth 3: the eighth cells above the tolerance
  long long points = 0, failed = 0;  // points solved in this run, of which failed
  double largest_error = 0;          // the largest relative estimate over the cells
};

// Finds the cells (8 stored corners joined by the moves of the lowest one; either probe) whose
// estimated error (refine_indicator.h, the largest over the cell's 19 recorded moves) exceeds the
// tolerance times the largest force at the cell's corners and midpoints, and solves the 98 new
// points of each that has none yet (depth 1) and, at depth 2, the 604 points of its eighth-spacing
// lattice that it lacks; at depth 3, once every flagged cell has those, the sixteenth-spacing
// points (up to 19 each) of the eighth cells whose estimate from the eighth-spacing lattice and
// its flagged face neighbours' (flag_eighth_cells) exceeds kSixteenthToleranceFactor times the
// tolerance times the cell's largest force. One cell per catalogue transaction, so a run killed or
// stopped (stop_requested) resumes with the next cell. Each point is solved from the nearest
// corner's stored state. Records a "refine" stage run; "unchanged" when no flagged cell is left.
// With a contact probe each point is a contact solve from that corner, as the expansion's moves are
// (the cells clear of the body have no force and are never flagged). Throws InputError if the
// directory is not expanded.
RefineReport run_refine(const RefineOptions& options);

}  // namespace hapstate
