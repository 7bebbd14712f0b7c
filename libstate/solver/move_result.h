// The outcome of one move of the path solver (PathSolver::move_to): success or the failure
// class and reason, and what the move cost.
#pragma once

#include <string>
#include <vector>

namespace hapstate {

enum class SolveFailure {
  kNone = 0,
  kMaxIterations = 1,     // Newton did not reach the tolerance within max_iterations
  kInverted = 2,          // every trial step inverted an element (J <= 0)
  kNotFinite = 3,         // NaN or infinity in the residual
  kLineSearch = 4,        // no step along the Newton direction reduced energy or residual
  kCutbackLimit = 5,      // the sub-step was halved max_cutbacks times and still failed
  kContactCycle = 6,      // contact: the touched set came back to an earlier set (oscillates)
  kContactUnsettled = 7,  // contact: the touched set still changed after the iteration cap
};
const char* failure_name(SolveFailure f);

struct MoveResult {
  bool ok = true;
  SolveFailure failure = SolveFailure::kNone;
  std::string reason;      // human-readable failure reason (empty if ok)
  int substeps = 0;        // accepted sub-steps
  int cutbacks = 0;        // sub-step halvings
  int iterations = 0;      // Newton iterations (linear solves, predictors included)
  int factorisations = 0;  // numeric factorisations, PSD fallbacks included
  // Of those, the factorisations of the move's start state that the fast algorithm keeps for the
  // next move from the same state (0 when this move reused them): shared by every direction of
  // a configuration's expansion, so the expansion records them apart from the transition's own.
  int start_factorisations = 0;
  double residual = 0;  // final ||r_free|| [N]
  double wall_ms = 0;
  int active_set_iterations = 0;  // contact: touched-set changes (stick) or multiplier updates
                                  // followed by a re-solve (frictionless) over the whole move
  std::vector<double> residual_history;  // ||r_free|| of the last Newton solve, per iteration
  // 1 when the move converged as one move; else the number of equal pieces it was split into by
  // the fallback of PathSolver::move_to (kMoveSplits) after the one move failed.
  int split_pieces = 1;
};

}  // namespace hapstate
