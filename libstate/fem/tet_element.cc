#include "fem/tet_element.h"

#include <Eigen/LU>

#include <limits>

namespace hapstate {

TetGeometry make_tet_geometry(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                              const Eigen::Vector3d& x2, const Eigen::Vector3d& x3) {
  Mat3 dm;
  dm.col(0) = x1 - x0;
  dm.col(1) = x2 - x0;
  dm.col(2) = x3 - x0;
  const Mat3 dm_inv = dm.inverse();
  TetGeometry g;
  g.volume = dm.determinant() / 6.0;
  // N_b = row (b-1) of dm_inv applied to (X - x0) for b = 1..3; N_0 = 1 - N_1 - N_2 - N_3.
  g.grad.row(1) = dm_inv.row(0);
  g.grad.row(2) = dm_inv.row(1);
  g.grad.row(3) = dm_inv.row(2);
  g.grad.row(0) = -(dm_inv.row(0) + dm_inv.row(1) + dm_inv.row(2));
  return g;
}

Mat3 deformation_gradient(const TetGeometry& g, const Vec12& u_e) {
  Mat3 f = Mat3::Identity();
  for (int a = 0; a < 4; ++a) f += u_e.segment<3>(3 * a) * g.grad.row(a);
  return f;
}

double tet_energy(const TetGeometry& g, const Material& material, const Vec12& u_e,
                  Vec12* force, Mat12* stiffness) {
  const Mat3 f = deformation_gradient(g, u_e);
  if (material.requires_positive_jacobian() && !(f.determinant() > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  Mat3 p;
  Mat9 a;
  const double w = material.evaluate(f, force ? &p : nullptr, stiffness ? &a : nullptr);
  if (force) {
    // dW/du_{a,i} = sum_j P(i,j) grad(a,j)
    for (int n = 0; n < 4; ++n) force->segment<3>(3 * n) = g.volume * (p * g.grad.row(n).transpose());
  }
  if (stiffness) {
    // B (9x12): d vecF(i+3j) / d u(3a+i') = delta(i,i') grad(a,j); K = V B^T A B.
    Eigen::Matrix<double, 9, 12> b = Eigen::Matrix<double, 9, 12>::Zero();
    for (int n = 0; n < 4; ++n)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) b(i + 3 * j, 3 * n + i) = g.grad(n, j);
    const Eigen::Matrix<double, 9, 12> ab = a * b;
    stiffness->noalias() = g.volume * (b.transpose() * ab);
  }
  return g.volume * w;
}

}  // namespace hapstate
