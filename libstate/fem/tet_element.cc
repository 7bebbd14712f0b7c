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

double tet_energy(const TetGeometry& g, const Material& material, const Vec12& u_e, Vec12* force,
                  Mat12* stiffness) {
  const Mat3 f = deformation_gradient(g, u_e);
  if (material.requires_positive_jacobian() && !(f.determinant() > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  Mat3 p;
  Mat9 a;
  const double w = material.evaluate(f, force ? &p : nullptr, stiffness ? &a : nullptr);
  if (force) {
    // dW/du_{a,i} = sum_j P(i,j) grad(a,j)
    for (int n = 0; n < 4; ++n)
      force->segment<3>(3 * n) = g.volume * (p * g.grad.row(n).transpose());
  }
  if (stiffness) {
    // K(3a+i, 3b+k) = V sum_{j,l} A(i+3j, k+3l) grad(a,j) grad(b,l), using the sparsity of
    // d vecF / d u_e: first H_a(i, k+3l) = sum_j A(i+3j, k+3l) grad(a,j), then contract with b.
    Eigen::Matrix<double, 3, 9> h[4];
    for (int n = 0; n < 4; ++n) {
      h[n] = g.grad(n, 0) * a.block<3, 9>(0, 0) + g.grad(n, 1) * a.block<3, 9>(3, 0) +
             g.grad(n, 2) * a.block<3, 9>(6, 0);
    }
    for (int na = 0; na < 4; ++na) {
      for (int nb = na; nb < 4; ++nb) {
        const Mat3 kab = g.volume * (g.grad(nb, 0) * h[na].block<3, 3>(0, 0) +
                                     g.grad(nb, 1) * h[na].block<3, 3>(0, 3) +
                                     g.grad(nb, 2) * h[na].block<3, 3>(0, 6));
        stiffness->block<3, 3>(3 * na, 3 * nb) = kab;
        if (nb != na) stiffness->block<3, 3>(3 * nb, 3 * na) = kab.transpose();
      }
    }
  }
  return g.volume * w;
}

}  // namespace hapstate
