#include "solver/sphere_query.h"

#include <algorithm>
#include <cmath>

namespace hapstate {
namespace {

std::int64_t cell_coord(double x, double cell) {
  return static_cast<std::int64_t>(std::floor(x / cell));
}

}  // namespace

std::uint64_t SphereQuery::bucket_of(std::int64_t i, std::int64_t j, std::int64_t k) const {
  // Large odd multipliers spread neighbouring cells over the table; collisions only cost a few
  // extra distance tests, never a wrong answer.
  const auto h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
                 static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^
                 static_cast<std::uint64_t>(k) * 0x165667B19E3779F9ull;
  return (h ^ (h >> 29)) & mask_;
}

void SphereQuery::build(const Eigen::Matrix3Xd& points, double cell) {
  points_ = points;
  cell_ = cell;
  const auto n = static_cast<std::uint64_t>(points.cols());
  std::uint64_t buckets = 16;
  while (buckets < 2 * n) buckets *= 2;
  mask_ = buckets - 1;
  std::vector<std::uint64_t> bucket(n);
  start_.assign(buckets + 1, 0);
  for (std::uint64_t p = 0; p < n; ++p) {
    bucket[p] = bucket_of(cell_coord(points(0, p), cell), cell_coord(points(1, p), cell),
                          cell_coord(points(2, p), cell));
    ++start_[bucket[p] + 1];
  }
  for (std::uint64_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  order_.resize(n);
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::uint64_t p = 0; p < n; ++p) order_[fill[bucket[p]]++] = static_cast<int>(p);
}

void SphereQuery::inside(const Eigen::Vector3d& centre, double radius,
                         std::vector<int>* out) const {
  if (points_.cols() == 0) return;
  const std::size_t first = out->size();
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = cell_coord(centre[a] - radius, cell_);
    hi[a] = cell_coord(centre[a] + radius, cell_);
  }
  const double r2 = radius * radius;
  // A sphere much larger than the cells would visit many empty cells: scan instead.
  const double cells =
      static_cast<double>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  if (cells > static_cast<double>(points_.cols())) {
    for (int p = 0; p < points_.cols(); ++p)
      if ((points_.col(p) - centre).squaredNorm() < r2) out->push_back(p);
    return;
  }
  std::vector<std::uint64_t> visited;
  for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
        const std::uint64_t b = bucket_of(i, j, k);
        // Two cells of the query may share a bucket: scan each bucket once.
        if (std::find(visited.begin(), visited.end(), b) != visited.end()) continue;
        visited.push_back(b);
        for (int s = start_[b]; s < start_[b + 1]; ++s) {
          const int p = order_[s];
          if ((points_.col(p) - centre).squaredNorm() < r2) out->push_back(p);
        }
      }
  std::sort(out->begin() + static_cast<std::ptrdiff_t>(first), out->end());
}

void points_inside_by_scan(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& centre,
                           double radius, std::vector<int>* out) {
  const double r2 = radius * radius;
  for (int p = 0; p < points.cols(); ++p)
    if ((points.col(p) - centre).squaredNorm() < r2) out->push_back(p);
}

}  // namespace hapstate
