#include "solver/rest_state.h"

#include "solver/path_solver.h"

#include <algorithm>

namespace hapstate {

RestState solve_rest_state(const Problem& problem) {
  RestState rest;
  rest.u_m.setZero(3 * problem.mesh.num_nodes());
  if (!problem.loads.has_force()) return rest;
  Problem free = problem;  // the probe holds nothing while the body settles
  free.constraints.probe_nodes.clear();
  for (DofRole& role : free.constraints.role)
    if (role == DofRole::kProbe) role = DofRole::kFree;
  free.contact.reset();
  free.rest_m.resize(0);
  PathSolver solver(free);
  rest.result = solver.settle_under_loads();
  rest.u_m = solver.state_m();
  for (int n = 0; n < problem.mesh.num_nodes(); ++n)
    rest.largest_sag = std::max(rest.largest_sag, rest.u_m.segment<3>(3 * n).norm() / problem.unit);
  return rest;
}

}  // namespace hapstate
