// The point of a triangle closest to a point (the geometry of frictionless sphere contact: the
// solver's contact, the rest clearance of hapstate-index and the haptic cursor's contact onset).
// Fixed-size, no heap.
#pragma once

#include <Eigen/Core>

namespace hapstate {

struct TrianglePoint {
  double distance = 0;                                // |q - p|
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();  // barycentric coordinates of p
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();  // p, the closest point of the triangle
};

// The point of triangle (a, b, c) closest to q (any triangle that is not degenerate to a point;
// a needle still gets its closest point on an edge).
TrianglePoint closest_point(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& q);

}  // namespace hapstate
