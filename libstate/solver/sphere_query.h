// Which points of a set lie inside a sphere: a uniform grid hash over the points (cell size
// chosen by the caller, typically the sphere radius), built in O(n). Used by the contact probe
// on the rest surface (grid classification, moves between free check-points): one build, many
// queries, as fast as a nanoflann k-d tree there and without the dependency. The deformed
// surface is scanned instead (docs/contact.md has the measurements).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hapstate {

class SphereQuery {
 public:
  // Indexes the columns of `points` (3 x n) in cells of edge `cell` (> 0). The points are
  // copied; later changes to `points` need another build.
  void build(const Eigen::Matrix3Xd& points, double cell);
  // Appends to `out` the indices of the points p with |p - centre| < radius, ascending.
  void inside(const Eigen::Vector3d& centre, double radius, std::vector<int>* out) const;
  int size() const { return static_cast<int>(points_.cols()); }

 private:
  std::uint64_t bucket_of(std::int64_t i, std::int64_t j, std::int64_t k) const;

  Eigen::Matrix3Xd points_;
  double cell_ = 1;
  std::uint64_t mask_ = 0;
  std::vector<int> start_;  // bucket b holds order_[start_[b] .. start_[b + 1])
  std::vector<int> order_;  // point indices sorted by bucket
};

// The same answer by scanning every point (the tests' reference).
void points_inside_by_scan(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& centre,
                           double radius, std::vector<int>* out);

}  // namespace hapstate
