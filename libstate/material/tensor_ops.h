// Internal helpers that build 9x9 fourth-order tensors A(i + 3j, k + 3l) from 3x3 factors,
// using the flattening of material.h. Fixed-size, allocation-free, header-only.
#pragma once

#include "material/material.h"

#include <Eigen/Geometry>  // cross()

namespace hapstate::detail {

// A += s * vec(X) vec(Y)^T, i.e. A_ijkl += s X_ij Y_kl.
inline void add_outer(Mat9& A, double s, const Mat3& X, const Mat3& Y) {
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> x(X.data()), y(Y.data());
  A.noalias() += (s * x) * y.transpose();
}

// A_ijkl += s X_il Y_kj (symmetric in (ij) <-> (kl) when X == Y).
inline void add_crossed(Mat9& A, double s, const Mat3& X, const Mat3& Y) {
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) A(i + 3 * j, k + 3 * l) += s * X(i, l) * Y(k, j);
}

// A_ijkl += s delta_ik X_lj (X symmetric keeps A symmetric).
inline void add_left_identity(Mat9& A, double s, const Mat3& X) {
  for (int l = 0; l < 3; ++l)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) A(i + 3 * j, i + 3 * l) += s * X(l, j);
}

// A_ijkl += s X_ik delta_jl (X symmetric keeps A symmetric).
inline void add_right_identity(Mat9& A, double s, const Mat3& X) {
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) A(i + 3 * j, k + 3 * j) += s * X(i, k);
}

// Cofactor matrix cof(F) = det(F) F^{-T}, defined for every F (also det F <= 0).
inline Mat3 cofactor(const Mat3& F) {
  Mat3 c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

}  // namespace hapstate::detail
