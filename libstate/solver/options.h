// Options of the path solver (scene [solver] table).
#pragma once

namespace hapstate {

// The contact probe's friction (scene probe.friction): kNone, frictionless sliding against the
// surface triangles (the default); kStick, surface nodes stick to the sphere where it caught them.
enum class Friction { kNone, kStick };

struct SolverOptions {
  int substeps = 4;              // incremental-load steps per move between check-points
  double tolerance = 1e-8;       // Newton: relative residual (w.r.t. the reference force scale)
  double absolute_tolerance = 1e-12;  // Newton: absolute residual floor [N]
  int max_iterations = 30;       // Newton iterations per sub-step target
  int max_cutbacks = 8;          // halvings of a sub-step after a failed Newton solve
  int max_active_set_iterations = 20;  // contact: touched-set changes per sub-step
};

}  // namespace hapstate
