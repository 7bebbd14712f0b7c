#include "solver/contact_set.h"

#include "util/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace hapstate {

ContactSet::ContactSet(const Eigen::Matrix3Xd& reference, const ContactSphere& sphere,
                       const Eigen::Vector3d& centre_rest)
    : reference_(reference),
      radius_(sphere.radius),
      candidates_(sphere.candidates),
      is_candidate_(static_cast<std::size_t>(reference.cols()), 0),
      centre_rest_(centre_rest) {
  for (int n : candidates_) is_candidate_[static_cast<std::size_t>(n)] = 1;
}

Eigen::Vector3d ContactSet::prescribed(int k, const Eigen::Vector3d& centre) const {
  return centre + anchors_[static_cast<std::size_t>(k)] - reference_.col(touched_[k]);
}

// The deformed surface moves between queries, so any index would be rebuilt every time; a
// plain scan is measured faster than rebuilding our grid hash or a k-d tree
// (bench/contact_bench, docs/contact.md).
std::vector<int> ContactSet::penetrating(const Eigen::VectorXd& u_m, double unit,
                                         const Eigen::Vector3d& centre) {
  const auto start = std::chrono::steady_clock::now();
  const double reach = radius_ * (1.0 - kPenetrationTolerance);
  const double reach2 = reach * reach;
  const double inverse_unit = 1.0 / unit;
  std::vector<int> inside;
  for (int n : candidates_) {
    const Eigen::Vector3d x = reference_.col(n) + u_m.segment<3>(3 * n) * inverse_unit;
    if ((x - centre).squaredNorm() < reach2) inside.push_back(n);
  }
  timings_.detection +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++timings_.queries;
  return inside;  // candidates_ is ascending, so is this
}

ContactChange ContactSet::decide(const Eigen::VectorXd& u_m, double unit, const Eigen::VectorXd& f,
                                 const Eigen::Vector3d& centre, double absolute_tolerance) {
  ContactChange change;
  double largest = 0;
  for (int n : touched_) largest = std::max(largest, f.segment<3>(3 * n).norm());
  const double tolerance = std::max(absolute_tolerance, kAdhesionTolerance * largest);
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    const int n = touched_[k];
    // f is the force the sphere applies to the body; pushing is along +anchor (out of the
    // sphere), so a negative normal component means the body holds on to the sphere.
    const double push = f.segment<3>(3 * n).dot(anchors_[k]) / radius_;
    if (push < -tolerance) change.released.push_back(n);
  }
  for (int n : penetrating(u_m, unit, centre))
    if (!std::binary_search(touched_.begin(), touched_.end(), n)) change.added.push_back(n);
  return change;
}

Eigen::Vector3d ContactSet::anchor_of(int node, const Eigen::VectorXd& u_m, double unit,
                                      const Eigen::Vector3d& centre) const {
  Eigen::Vector3d ray = reference_.col(node) + u_m.segment<3>(3 * node) / unit - centre;
  // A node exactly at the centre has no ray: push it out along its rest direction instead.
  if (ray.norm() <= 1e-12 * radius_) ray = reference_.col(node) - centre_rest_;
  if (ray.norm() <= 1e-12 * radius_) ray = Eigen::Vector3d::UnitZ();
  return radius_ * ray.normalized();
}

void ContactSet::apply(const ContactChange& change, const Eigen::VectorXd& u_m, double unit,
                       const Eigen::Vector3d& centre) {
  std::vector<int> nodes;
  std::vector<Eigen::Vector3d> anchors;
  std::size_t a = 0;
  auto add_until = [&](int limit) {
    while (a < change.added.size() && change.added[a] < limit) {
      nodes.push_back(change.added[a]);
      anchors.push_back(anchor_of(change.added[a], u_m, unit, centre));
      ++a;
    }
  };
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    const int n = touched_[k];
    add_until(n);
    if (std::binary_search(change.released.begin(), change.released.end(), n)) continue;
    nodes.push_back(n);
    anchors.push_back(anchors_[k]);
  }
  add_until(static_cast<int>(reference_.cols()));
  touched_ = std::move(nodes);
  anchors_ = std::move(anchors);
}

void ContactSet::assign(const std::vector<int>& nodes, const Eigen::VectorXd& u_m, double unit,
                        const Eigen::Vector3d& centre) {
  std::vector<int> sorted = nodes;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  touched_.clear();
  anchors_.clear();
  for (int n : sorted) {
    if (n < 0 || n >= reference_.cols() || !is_candidate_[static_cast<std::size_t>(n)])
      throw InputError("touched node " + std::to_string(n) +
                       " is not a surface node the contact probe may touch");
    touched_.push_back(n);
    anchors_.push_back(anchor_of(n, u_m, unit, centre));
  }
}

}  // namespace hapstate
