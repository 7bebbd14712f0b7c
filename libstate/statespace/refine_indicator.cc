#include "statespace/refine_indicator.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace hapstate {
namespace {

// The weights of the six data (value and derivative at s = 0, 1/2, 1) in the quintic Hermite
// interpolant's value at s = 1/4 (row 0) and s = 3/4 (row 1).
Eigen::Matrix<double, 2, 6> quintic_weights() {
  Eigen::Matrix<double, 6, 6> A;  // rows: the conditions; columns: the monomials s^0 .. s^5
  const double nodes[3] = {0.0, 0.5, 1.0};
  for (int n = 0; n < 3; ++n)
    for (int k = 0; k < 6; ++k) {
      A(2 * n, k) = std::pow(nodes[n], k);
      A(2 * n + 1, k) = k == 0 ? 0.0 : k * std::pow(nodes[n], k - 1);
    }
  const Eigen::Matrix<double, 6, 6> inverse = A.inverse();
  Eigen::Matrix<double, 2, 6> w;
  for (int q = 0; q < 2; ++q) {
    Eigen::Matrix<double, 1, 6> monomials;
    for (int k = 0; k < 6; ++k) monomials(k) = std::pow(0.25 + 0.5 * q, k);
    w.row(q) = monomials * inverse;
  }
  return w;
}

}  // namespace

double half_spacing_error(const RecordedMove& move) {
  static const Eigen::Matrix<double, 2, 6> w = quintic_weights();
  double worst = 0.0;
  for (int r = 0; r < 3; ++r) {
    Eigen::Matrix<double, 6, 1> data;
    for (int n = 0; n < 3; ++n) data(2 * n) = move.force[n][r], data(2 * n + 1) = move.slope[n][r];
    const Eigen::Vector2d quintic = w * data;
    // Each cubic piece (length 1/2) at its middle: the mean of its ends plus (1/2)/8 of the
    // difference of their slopes.
    const double lower = 0.5 * (data(0) + data(2)) + (data(1) - data(3)) / 16.0;
    const double upper = 0.5 * (data(2) + data(4)) + (data(3) - data(5)) / 16.0;
    worst = std::max({worst, std::abs(quintic(0) - lower), std::abs(quintic(1) - upper)});
  }
  return std::isfinite(worst) ? worst : 0.0;
}

}  // namespace hapstate
