#include "solver/sliding_contact.h"

#include "solver/triangle_distance.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace hapstate {
namespace {

// The index of entry (row, col), row <= col, in the values of `pattern`.
int entry_of(const SymmetricPattern& pattern, int row, int col) {
  const auto begin = pattern.row_idx.begin() + pattern.col_ptr[col];
  const auto end = pattern.row_idx.begin() + pattern.col_ptr[col + 1];
  const auto it = std::lower_bound(begin, end, row);
  if (it == end || *it != row)
    throw std::logic_error("sliding contact: a surface triangle's DOF pair is not in the pattern");
  return static_cast<int>(it - pattern.row_idx.begin());
}

// A triangle's distance to the centre below which it is not culled: reach + a bounding box test.
bool box_reaches(const std::array<Eigen::Vector3d, 3>& x, const Eigen::Vector3d& centre,
                 double reach) {
  for (int c = 0; c < 3; ++c) {
    const double lo = std::min({x[0][c], x[1][c], x[2][c]});
    const double hi = std::max({x[0][c], x[1][c], x[2][c]});
    if (centre[c] < lo - reach || centre[c] > hi + reach) return false;
  }
  return true;
}

}  // namespace

SlidingContact::SlidingContact(const Eigen::Matrix3Xd& positions_m, const Triangles& surface,
                               double radius_m, double penalty, const SymmetricPattern& pattern)
    : reference_(positions_m),
      triangles_(surface),
      radius_(radius_m),
      base_penalty_(penalty),
      lambda_(static_cast<std::size_t>(surface.cols()), 0.0) {
  scatter_.resize(static_cast<std::size_t>(surface.cols()));
  for (int t = 0; t < surface.cols(); ++t) {
    int k = 0;
    for (int p = 0; p < 9; ++p)
      for (int q = p; q < 9; ++q) {
        const int gp = 3 * surface(p / 3, t) + p % 3, gq = 3 * surface(q / 3, t) + q % 3;
        scatter_[t][k++] = entry_of(pattern, std::min(gp, gq), std::max(gp, gq));
      }
  }
}

const std::vector<SlidingContact::Active>& SlidingContact::active(
    const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const {
  const auto start = std::chrono::steady_clock::now();
  active_.clear();
  const double inverse_k = 1.0 / penalty();
  for (int t = 0; t < triangles_.cols(); ++t) {
    std::array<Eigen::Vector3d, 3> x;
    for (int i = 0; i < 3; ++i) {
      const int n = triangles_(i, t);
      x[i] = reference_.col(n) + u_m.segment<3>(3 * n);
    }
    const double lambda = lambda_[static_cast<std::size_t>(t)];
    // lambda^ > 0 iff d < r + lambda / k.
    if (!box_reaches(x, centre_m, radius_ + lambda * inverse_k)) continue;
    const TrianglePoint tp = closest_point(x[0], x[1], x[2], centre_m);
    const double lambda_hat = lambda - penalty() * (tp.distance - radius_);
    if (lambda_hat > 0) active_.push_back({t, lambda_hat, x});
  }
  detection_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++queries_;
  return active_;
}

double SlidingContact::add_force(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                                 Eigen::VectorXd* f) const {
  // Triangles with lambda^ = 0 contribute -lambda^2 / 2k: summed over all multipliers.
  double e = 0;
  for (double l : lambda_) e -= l * l;
  for (const Active& a : active(u_m, centre_m)) {
    e += a.lambda_hat * a.lambda_hat;
    const TrianglePoint tp = closest_point(a.x[0], a.x[1], a.x[2], centre_m);
    if (tp.distance <= 0) continue;
    const Eigen::Vector3d normal = (centre_m - tp.closest) / tp.distance;
    // dPsi/dx_i = -lambda^ dd/dx_i = lambda^ w_i n.
    for (int i = 0; i < 3; ++i)
      f->segment<3>(3 * triangles_(i, a.triangle)) += a.lambda_hat * tp.weights[i] * normal;
  }
  return e / (2 * penalty());
}

// The Hessian of triangle a's term of Psi with respect to (its three corners, the centre), with
// penalty k in the positive part; psd_only drops the curvature term -lambda^ hess d.
Mat12d SlidingContact::term_hessian(const Active& a, const Eigen::Vector3d& centre_m, double k,
                                    bool psd_only) const {
  const TrianglePoint tp = closest_point(a.x[0], a.x[1], a.x[2], centre_m);
  if (tp.distance <= 0) return Mat12d::Zero();
  Vec12d g;
  Mat12d h;
  distance_derivatives(a.x[0], a.x[1], a.x[2], centre_m, tp, &g, &h);
  Mat12d local = k * g * g.transpose();
  if (!psd_only) local -= a.lambda_hat * h;
  return local;
}

void SlidingContact::add_tangent(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                                 std::vector<double>* k_values, bool psd_only,
                                 double hessian_penalty) const {
  const double k = hessian_penalty > 0 ? hessian_penalty : penalty();
  for (const Active& a : active(u_m, centre_m)) {
    Eigen::Matrix<double, 9, 9> local = term_hessian(a, centre_m, k, false).topLeftCorner<9, 9>();
    if (psd_only) {
      // The curvature term makes a term indefinite (a face tilting around the sphere): keep
      // the positive part of its spectrum, a descent direction for Newton.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(local);
      local = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
              eig.eigenvectors().transpose();
    }
    const auto& index = scatter_[static_cast<std::size_t>(a.triangle)];
    int e = 0;
    for (int p = 0; p < 9; ++p)
      for (int q = p; q < 9; ++q) (*k_values)[index[e++]] += local(p, q);
  }
}

void SlidingContact::add_coupling(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m,
                                  Eigen::Matrix<double, Eigen::Dynamic, 3>* k_uc,
                                  Eigen::Matrix3d* k_cc, double hessian_penalty) const {
  const double k = hessian_penalty > 0 ? hessian_penalty : penalty();
  for (const Active& a : active(u_m, centre_m)) {
    const Mat12d local = term_hessian(a, centre_m, k, false);
    for (int i = 0; i < 3; ++i)
      k_uc->middleRows<3>(3 * triangles_(i, a.triangle)) += local.block<3, 3>(3 * i, 9);
    *k_cc += local.block<3, 3>(9, 9);
  }
}

Eigen::Vector3d SlidingContact::force_on_probe(const Eigen::VectorXd& u_m,
                                               const Eigen::Vector3d& centre_m) const {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (const Active& a : active(u_m, centre_m)) {
    const TrianglePoint tp = closest_point(a.x[0], a.x[1], a.x[2], centre_m);
    if (tp.distance > 0) force += a.lambda_hat * (centre_m - tp.closest) / tp.distance;
  }
  return force;
}

std::vector<double> SlidingContact::sparse_multipliers() const {
  std::vector<double> pairs;
  for (std::size_t t = 0; t < lambda_.size(); ++t)
    if (lambda_[t] > 0) {
      pairs.push_back(static_cast<double>(t));
      pairs.push_back(lambda_[t]);
    }
  return pairs;
}

bool SlidingContact::set_sparse_multipliers(const std::vector<double>& pairs) {
  if (pairs.size() % 2 != 0) return false;
  std::vector<double> lambda(lambda_.size(), 0.0);
  for (std::size_t k = 0; k < pairs.size(); k += 2) {
    const double t = pairs[k], l = pairs[k + 1];
    if (!(t >= 0 && t < static_cast<double>(lambda.size()) && t == std::floor(t) &&
          std::isfinite(l) && l >= 0))
      return false;
    lambda[static_cast<std::size_t>(t)] = l;
  }
  lambda_ = std::move(lambda);
  return true;
}

std::vector<double> SlidingContact::updated(const Eigen::VectorXd& u_m,
                                            const Eigen::Vector3d& centre_m,
                                            double* worst_change) const {
  std::vector<double> hat(lambda_.size(), 0.0);
  for (const Active& a : active(u_m, centre_m))
    hat[static_cast<std::size_t>(a.triangle)] = a.lambda_hat;
  double worst = 0;
  for (std::size_t t = 0; t < lambda_.size(); ++t)
    worst = std::max(worst, std::abs(hat[t] - lambda_[t]));
  *worst_change = worst / penalty();
  return hat;
}

double SlidingContact::violation(const Eigen::VectorXd& u_m,
                                 const Eigen::Vector3d& centre_m) const {
  double worst = 0;
  updated(u_m, centre_m, &worst);
  return worst;
}

double SlidingContact::update_multipliers(const Eigen::VectorXd& u_m,
                                          const Eigen::Vector3d& centre_m) {
  double worst = 0;
  lambda_ = updated(u_m, centre_m, &worst);
  return worst;
}

bool SlidingContact::any_active(const Eigen::VectorXd& u_m, const Eigen::Vector3d& centre_m) const {
  return !active(u_m, centre_m).empty();
}

std::vector<int> SlidingContact::touched_nodes(const Eigen::VectorXd& u_m,
                                               const Eigen::Vector3d& centre_m) const {
  std::vector<int> nodes;
  for (const Active& a : active(u_m, centre_m))
    for (int i = 0; i < 3; ++i) nodes.push_back(triangles_(i, a.triangle));
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace hapstate
