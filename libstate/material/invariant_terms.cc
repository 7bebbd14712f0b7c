// Derivatives, with g = F^{-T}, dJ/dF = J g, dg_ij/dF_kl = -g_il g_kj, dI1/dF = 2F:
//  I1bar: P = c10 a (2F - 2/3 I1 g), a = J^(-2/3);
//         A = c10 a [2 d_ik d_jl - 4/3 (F(x)g + g(x)F) + 4/9 I1 g(x)g + 2/3 I1 g_il g_kj].
//  I2bar: with M = I1 F - F C (dI2/dF = 2M), b = J^(-4/3), B = F F^T:
//         P = c01 b (2M - 4/3 I2 g);
//         A = c01 b [4 F(x)F + 2 I1 d_ik d_jl - 2 (d_ik C_lj + F_il F_kj + B_ik d_jl)
//                    - 8/3 (g(x)M + M(x)g) + 16/9 I2 g(x)g + 4/3 I2 g_il g_kj].
//  volumetric: P = 2/d1 (J - 1) J g;  A = 2/d1 [(2J - 1) J g(x)g - (J - 1) J g_il g_kj].
#include "material/invariant_terms.h"

#include "material/tensor_ops.h"

#include <cmath>
#include <limits>

namespace hapstate::detail {

Kinematics::Kinematics(const Mat3& F) : f(F) {
  const Mat3 cof = cofactor(F);
  j = F.col(0).dot(cof.col(0));
  i1 = F.squaredNorm();
  if (j > 0) inv_t = cof / j;
}

double add_i1bar_term(const Kinematics& k, double c10, Mat3* P, Mat9* A) {
  const double cbrt_j = std::cbrt(k.j);
  const double a = 1.0 / (cbrt_j * cbrt_j);
  const Mat3& F = k.f;
  const Mat3& g = k.inv_t;
  const double s = c10 * a;
  if (P) *P += s * (2.0 * F - (2.0 / 3.0) * k.i1 * g);
  if (A) {
    add_left_identity(*A, 2.0 * s, Mat3::Identity());
    add_outer(*A, -(4.0 / 3.0) * s, F, g);
    add_outer(*A, -(4.0 / 3.0) * s, g, F);
    add_outer(*A, (4.0 / 9.0) * s * k.i1, g, g);
    add_crossed(*A, (2.0 / 3.0) * s * k.i1, g, g);
  }
  return c10 * (a * k.i1 - 3.0);
}

double add_i2bar_term(const Kinematics& k, double c01, Mat3* P, Mat9* A) {
  const double cbrt_j = std::cbrt(k.j);
  const double b = 1.0 / (cbrt_j * cbrt_j * cbrt_j * cbrt_j);
  const Mat3& F = k.f;
  const Mat3& g = k.inv_t;
  const Mat3 C = F.transpose() * F;
  const double i2 = 0.5 * (k.i1 * k.i1 - C.squaredNorm());
  const double s = c01 * b;
  if (P || A) {
    const Mat3 M = k.i1 * F - F * C;
    if (P) *P += s * (2.0 * M - (4.0 / 3.0) * i2 * g);
    if (A) {
      add_outer(*A, 4.0 * s, F, F);
      add_left_identity(*A, 2.0 * s * k.i1, Mat3::Identity());
      add_left_identity(*A, -2.0 * s, C);
      add_crossed(*A, -2.0 * s, F, F);
      add_right_identity(*A, -2.0 * s, F * F.transpose());
      add_outer(*A, -(8.0 / 3.0) * s, g, M);
      add_outer(*A, -(8.0 / 3.0) * s, M, g);
      add_outer(*A, (16.0 / 9.0) * s * i2, g, g);
      add_crossed(*A, (4.0 / 3.0) * s * i2, g, g);
    }
  }
  return c01 * (b * i2 - 3.0);
}

double add_volumetric_term(const Kinematics& k, double d1, Mat3* P, Mat9* A) {
  const double j = k.j;
  const Mat3& g = k.inv_t;
  if (P) *P += (2.0 / d1) * (j - 1.0) * j * g;
  if (A) {
    add_outer(*A, (2.0 / d1) * (2.0 * j - 1.0) * j, g, g);
    add_crossed(*A, -(2.0 / d1) * (j - 1.0) * j, g, g);
  }
  return (j - 1.0) * (j - 1.0) / d1;
}

double inverted_result(Mat3* P, Mat9* A) {
  if (P) P->setZero();
  if (A) A->setZero();
  return std::numeric_limits<double>::infinity();
}

}  // namespace hapstate::detail
