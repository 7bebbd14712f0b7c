// Two equilibria at one probe position (docs/certificate.md, "When it is not good enough"): the
// precise solver reaches the position from either side along a direction. Where a contact probe
// presses a sharp vertex or a thin flap's tip, the surface can slide off the sphere to one side
// or the other and the force jumps where one of two equilibria ends: no interpolation follows a
// jump, so no grid spacing or refinement depth brings that error down. hapstate-certify runs
// this on its worst steps; Python's hapstate.equilibria on any position.
#pragma once

#include "catalogue/records.h"  // Equilibria, equilibria_name
#include "problem/problem.h"

#include <Eigen/Core>

#include <array>
#include <limits>

namespace hapstate {

// One approach: from rest to its start in `steps` equal moves (a contact sphere whose start is
// clear of the body is placed there instead), then sliding to the position in `steps` more.
struct Approach {
  bool started = false;    // every move from rest to the start converged
  bool converged = false;  // every move converged, the last (to the position) too
  Eigen::Vector3d force = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  // N: the force felt at the position; NaN unless converged
};

struct TwoSided {
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), along = Eigen::Vector3d::Zero();  // mesh units
  Approach minus, plus;  // by way of point - along and of point + along
  double difference = std::numeric_limits<double>::quiet_NaN();  // |f- - f+|, N; NaN unless both
  double largest = std::numeric_limits<double>::quiet_NaN();     // the larger |f| that converged, N
};

// Below this difference (N) two forces are the same whatever the tolerance: the solver's residual
// tolerance leaves far less, and a grazing contact's forces are round-off apart.
inline constexpr double kEquilibriaFloorN = 1e-7;

// The precise force at `point` (absolute, mesh units) reached both ways, each approach on a
// solver of its own starting at rest. Throws InputError for a non-finite point, a zero or
// non-finite `along`, or steps < 1.
Approach approach(const Problem& problem, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& start, int steps);
// The two approaches side by side: difference and largest from their forces.
TwoSided compare(const Eigen::Vector3d& point, const Eigen::Vector3d& along, const Approach& minus,
                 const Approach& plus);
TwoSided from_both_sides(const Problem& problem, const Eigen::Vector3d& point,
                         const Eigen::Vector3d& along, int steps = 10);
// Two forces differ when their difference exceeds tolerance x the larger force (and
// kEquilibriaFloorN). Throws InputError unless tolerance is a finite number > 0.
Equilibria judge(const TwoSided& r, double tolerance = 0.01);

// The default approaches: half the grid spacing along x, y and z.
std::array<Eigen::Vector3d, 3> half_spacing_approaches(const Eigen::Vector3d& spacing);

}  // namespace hapstate
