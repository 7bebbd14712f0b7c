#include "solver/triangle_distance.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace hapstate {
namespace {

// Closest points of segments [p0, p1] and [q0, q1]: the squared distance.
double segment_segment_distance2(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return r.squaredNorm();
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p0 + s * d1 - (q0 + t * d2)).squaredNorm();
}

}  // namespace

void distance_derivatives(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& q,
                          const TrianglePoint& tp, Vec12d* gradient, Mat12d* hessian) {
  const std::array<const Eigen::Vector3d*, 3> x{&a, &b, &c};
  const Eigen::Vector3d r = q - tp.closest;  // residual of the feature's least-squares problem
  const double d = tp.distance;
  // J = dr/dy at fixed feature parameters: -w_i I on corner i, I on q.
  Eigen::Matrix<double, 3, 12> jac = Eigen::Matrix<double, 3, 12>::Zero();
  for (int i = 0; i < 3; ++i) jac.block<3, 3>(0, 3 * i).diagonal().setConstant(-tp.weights[i]);
  jac.block<3, 3>(0, 9).setIdentity();
  const Vec12d grad_big_d = jac.transpose() * r;  // grad of D = d^2 / 2
  Mat12d hess_big_d = jac.transpose() * jac;
  // The closest feature: the corners with a non-zero weight (1, 2 or 3 of them).
  std::array<int, 3> corners{};
  int k = 0;
  for (int i = 0; i < 3; ++i)
    if (tp.weights[i] > 0) corners[k++] = i;
  if (k >= 2) {
    // p = x_base + E s, columns e_j = x_{corner j} - x_base.
    const int base = corners[0], m = k - 1;
    Eigen::Matrix<double, 3, 2> e;
    Eigen::Matrix<double, 12, 2> f_ys = Eigen::Matrix<double, 12, 2>::Zero();
    for (int j = 0; j < m; ++j) {
      const int v = corners[j + 1];
      e.col(j) = *x[v] - *x[base];
      // f_{y s_j} = -(d e_j / dy)^T r - J^T e_j.
      Vec12d col = -jac.transpose() * e.col(j);
      col.segment<3>(3 * v) -= r;
      col.segment<3>(3 * base) += r;
      f_ys.col(j) = col;
    }
    if (m == 1) {
      hess_big_d -= f_ys.col(0) * f_ys.col(0).transpose() / e.col(0).squaredNorm();
    } else {
      const Eigen::Matrix2d gram = e.transpose() * e;
      hess_big_d -= f_ys * gram.inverse() * f_ys.transpose();
    }
  }
  *gradient = grad_big_d / d;
  *hessian = (hess_big_d - (*gradient) * gradient->transpose()) / d;  // grad d = grad D / d
}

double segment_triangle_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c) {
  // Crossing: the segment meets the plane inside the triangle.
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double s0 = normal.dot(p0 - a), s1 = normal.dot(p1 - a);
  if ((s0 <= 0 && s1 >= 0) || (s0 >= 0 && s1 <= 0)) {
    if (s0 != s1) {
      const Eigen::Vector3d hit = p0 + (s0 / (s0 - s1)) * (p1 - p0);
      if (closest_point(a, b, c, hit).distance <= 1e-14 * (b - a).norm()) return 0.0;
    }
  }
  // Otherwise the closest pair has a segment end or lies on a triangle edge.
  double best2 = std::min(std::pow(closest_point(a, b, c, p0).distance, 2),
                          std::pow(closest_point(a, b, c, p1).distance, 2));
  best2 = std::min(best2, segment_segment_distance2(p0, p1, a, b));
  best2 = std::min(best2, segment_segment_distance2(p0, p1, b, c));
  best2 = std::min(best2, segment_segment_distance2(p0, p1, c, a));
  return std::sqrt(best2);
}

}  // namespace hapstate
