// The distance from a point to a triangle, with its exact first and second derivatives with
// respect to the triangle's three corners and the point: the geometry of frictionless sphere
// contact (solver/sliding_contact.h). Also the distance from a segment to a triangle (the
// sphere swept along a move). Fixed-size, no heap.
#pragma once

#include "util/triangle_point.h"

#include <Eigen/Core>

namespace hapstate {

using Vec12d = Eigen::Matrix<double, 12, 1>;
using Mat12d = Eigen::Matrix<double, 12, 12>;

// Gradient and Hessian of d = distance(q, triangle(a, b, c)) with respect to
// y = (a, b, c, q), at a point with d > 0 and `tp` = closest_point(a, b, c, q). Within each
// region of the closest feature (face, edge, vertex) d is smooth; across regions its gradient is
// continuous and the Hessian jumps. Derivation: with the feature parameterised as
// p = x0 + E s, D = d^2 / 2 = min_s f(y, s), so grad D = f_y and
// hess D = f_yy - f_ys (f_ss)^-1 f_sy at the optimum (docs/contact.md).
void distance_derivatives(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& q,
                          const TrianglePoint& tp, Vec12d* gradient, Mat12d* hessian);

// The smallest distance between segment [p0, p1] and triangle (a, b, c); 0 if they cross.
double segment_triangle_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c);

}  // namespace hapstate
