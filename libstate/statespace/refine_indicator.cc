#include "statespace/refine_indicator.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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

std::vector<LatticeSample> lattice_with_halo(
    const std::vector<LatticeSample>& own,
    const std::array<const std::vector<LatticeSample>*, 6>& neighbour) {
  std::vector<LatticeSample> out(std::size_t(kHaloSide * kHaloSide * kHaloSide));
  auto own_at = [](const std::vector<LatticeSample>& l, const int(&p)[3]) -> const LatticeSample& {
    return l.at(std::size_t(81 * p[0] + 9 * p[1] + p[2]));
  };
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      for (int k = 0; k < 9; ++k) out[halo_index(i, j, k)] = own_at(own, {i, j, k});
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const std::vector<LatticeSample>* other = neighbour[std::size_t(2 * a + side)];
      if (!other) continue;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int u = 0; u < 9; ++u)
        for (int v = 0; v < 9; ++v) {
          int here[3], there[3];
          here[a] = side ? 9 : -1, there[a] = side ? 1 : 7;
          here[b] = there[b] = u, here[c] = there[c] = v;
          out[halo_index(here[0], here[1], here[2])] = own_at(*other, there);
        }
    }
  return out;
}

std::vector<int> flag_eighth_cells(const std::vector<LatticeSample>& lattice,
                                   const std::array<double, 3>& spacing, double limit,
                                   double* largest) {
  if (lattice.size() != std::size_t(kHaloSide * kHaloSide * kHaloSide))
    throw std::invalid_argument("flag_eighth_cells: the lattice has " +
                                std::to_string(lattice.size()) + " samples, not 11^3");
  constexpr int n = 9;
  std::vector<bool> flagged(512, false);
  double worst = 0.0;
  auto at = [&](const int(&p)[3]) -> const LatticeSample& {
    return lattice[halo_index(p[0], p[1], p[2])];
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double length = 2.0 * spacing[a] / 8.0;  // the move: two eighth steps along a
    for (int u = 0; u < n; ++u)
      for (int v = 0; v < n; ++v)
        for (int first = -1; first + 2 <= n; ++first) {
          RecordedMove move;
          bool known = true;
          for (int m = 0; m < 3; ++m) {
            int p[3];
            p[a] = first + m, p[b] = u, p[c] = v;
            const LatticeSample& s = at(p);
            known = known && s.known;
            move.force[m] = s.force;
            for (int r = 0; r < 3; ++r) move.slope[m][r] = s.stiffness[3 * r + a] * length;
          }
          if (!known) continue;
          const double error = half_spacing_error(move);
          worst = std::max(worst, error);
          if (!(error > limit)) continue;
          // The eighth cells with the edge (first, first + 1) or (first + 1, first + 2) along a
          // at (u, v): those whose b and c steps are u - 1 or u, v - 1 or v.
          for (int e = first; e <= first + 1; ++e)
            for (int du = -1; du <= 0; ++du)
              for (int dv = -1; dv <= 0; ++dv) {
                int q[3];
                q[a] = e, q[b] = u + du, q[c] = v + dv;
                if (q[a] < 0 || q[a] > 7 || q[b] < 0 || q[b] > 7 || q[c] < 0 || q[c] > 7) continue;
                flagged[std::size_t(64 * q[0] + 8 * q[1] + q[2])] = true;
              }
        }
  }
  if (largest) *largest = worst;
  std::vector<int> out;
  for (int e = 0; e < 512; ++e)
    if (flagged[std::size_t(e)]) out.push_back(e);
  return out;
}

}  // namespace hapstate
