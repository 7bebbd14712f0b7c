#include "eval/equilibria.h"

#include "solver/path_solver.h"
#include "statespace/probe_model.h"
#include "util/error.h"

#include <algorithm>
#include <cmath>

namespace hapstate {

Approach approach(const Problem& problem, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& start, int steps) {
  if (!point.allFinite() || !start.allFinite())
    throw InputError("two-sided solve: the position and the approach must be finite");
  if (steps < 1)
    throw InputError("two-sided solve: steps must be >= 1 (got " + std::to_string(steps) + ")");
  PathSolver solver(problem);
  const Eigen::Vector3d rest = problem.probe_rest;
  Approach a;
  a.started = true;
  // A contact sphere whose start is clear of the body is placed there with the body at rest (as
  // eval starts a path): a straight move from rest could pass through a thin part and reach the
  // position from its other side. Otherwise it moves there from rest.
  if (!make_probe_model(problem)->start_path_at(solver, start))
    for (int k = 1; k <= steps && a.started; ++k)
      a.started = solver.move_to((start - rest) * (k / double(steps))).ok;
  if (!a.started) return a;
  a.converged = true;
  for (int k = 1; k <= steps && a.converged; ++k)
    a.converged = solver.move_to(start + (point - start) * (k / double(steps)) - rest).ok;
  if (a.converged) a.force = solver.force_felt();
  return a;
}

TwoSided compare(const Eigen::Vector3d& point, const Eigen::Vector3d& along, const Approach& minus,
                 const Approach& plus) {
  TwoSided r;
  r.point = point;
  r.along = along;
  r.minus = minus;
  r.plus = plus;
  if (r.minus.converged && r.plus.converged) r.difference = (r.minus.force - r.plus.force).norm();
  for (const Approach* a : {&r.minus, &r.plus})
    if (a->converged)
      r.largest = std::isnan(r.largest) ? a->force.norm() : std::max(r.largest, a->force.norm());
  return r;
}

TwoSided from_both_sides(const Problem& problem, const Eigen::Vector3d& point,
                         const Eigen::Vector3d& along, int steps) {
  if (!along.allFinite() || along.isZero(0.0))
    throw InputError("two-sided solve: along (the approach) must be finite and not zero");
  return compare(point, along, approach(problem, point, point - along, steps),
                 approach(problem, point, point + along, steps));
}

Equilibria judge(const TwoSided& r, double tolerance) {
  if (!(tolerance > 0 && std::isfinite(tolerance)))
    throw InputError("two-sided solve: the tolerance must be a number > 0 (got " +
                     std::to_string(tolerance) + ")");
  if (!(r.minus.started && r.plus.started)) return Equilibria::kUndecided;
  if (r.minus.converged != r.plus.converged) return Equilibria::kEnds;
  if (!r.minus.converged) return Equilibria::kUndecided;
  return r.difference > std::max(tolerance * r.largest, kEquilibriaFloorN) ? Equilibria::kTwo
                                                                           : Equilibria::kOne;
}

std::array<Eigen::Vector3d, 3> half_spacing_approaches(const Eigen::Vector3d& spacing) {
  std::array<Eigen::Vector3d, 3> out;
  for (int a = 0; a < 3; ++a) out[a] = 0.5 * spacing[a] * Eigen::Vector3d::Unit(a);
  return out;
}

}  // namespace hapstate
