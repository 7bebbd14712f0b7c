// The loaded rest state: the body's equilibrium under its own weight and its supports
// (Problem::loads) with the probe attached to nothing, found from the mesh as drawn by
// incremental loading (PathSolver::settle_under_loads). It is the state space's zero
// configuration: every probe path starts there and every stored displacement includes it.
#pragma once

#include "problem/problem.h"
#include "solver/move_result.h"

#include <Eigen/Core>

namespace hapstate {

struct RestState {
  Eigen::VectorXd u_m;     // metres, one value per DOF (the last converged state on failure)
  MoveResult result;       // substeps = load steps, iterations = Newton's linear solves
  double largest_sag = 0;  // the largest node displacement, mesh units
};

// The loaded rest state of `problem` (its grabbed DOFs free, its contact sphere away, its
// rest_m ignored). Without a body force the rest state is u = 0 and nothing is solved.
RestState solve_rest_state(const Problem& problem);

}  // namespace hapstate
