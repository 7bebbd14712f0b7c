// Options of the path solver (scene [solver] table).
#pragma once

namespace hapstate {

// The contact probe's friction (scene probe.friction): kNone, frictionless sliding against the
// surface triangles (the default); kStick, surface nodes stick to the sphere where it caught them.
enum class Friction { kNone, kStick };

// How a move is solved. kFast: grab and frictionless contact probes start with one sub-step for
// the whole move (halved on failure, grown back after two successes) and solve each Newton
// system by conjugate gradients preconditioned with a kept factorisation (inexact Newton; the
// factorisation of a move's start state is shared by every move from that state); a sticking
// contact probe, whose touched set decides the prescribed DOFs, solves as kReference.
// kReference: the paper's algorithm, `substeps` fixed sub-steps with full Newton (a
// factorisation per iteration); kept for tests and comparisons. Both converge to the same
// tolerance, so they store the same state space within it.
enum class SolverAlgorithm { kFast, kReference };

struct SolverOptions {
  SolverAlgorithm algorithm = SolverAlgorithm::kFast;  // not a scene key: tool option
  int substeps = 4;         // incremental-load steps per move (kReference, sticking
                            // contact; kFast's smallest sub-step derives from it)
  double tolerance = 1e-8;  // Newton: relative residual (w.r.t. the reference force scale)
  double absolute_tolerance = 1e-12;  // Newton: absolute residual floor [N]
  int max_iterations = 30;            // Newton iterations per sub-step target (up to 4x as many
                            // while the residual still halves every 10; path_solver_newton.cc)
  int max_cutbacks = 8;                // halvings of a sub-step after a failed Newton solve
  int max_active_set_iterations = 20;  // contact: touched-set changes (stick) or multiplier
                                       // updates (frictionless) per sub-step
  // Frictionless contact: a converged state has no surface point deeper inside the sphere than
  // gap_tolerance x radius, and no force on a triangle farther than that from it (not a scene
  // key; tests that difference equilibrium energies tighten it).
  double gap_tolerance = 1e-6;
  // Frictionless contact: the augmented Lagrangian's penalty, as a multiple of the median
  // diagonal stiffness of the free surface DOFs at rest, for a nearly incompressible material
  // (nu > 0.45) of its shear share (not a scene key; see solver/sliding_boundary.cc).
  double contact_penalty = 300;
};

}  // namespace hapstate
