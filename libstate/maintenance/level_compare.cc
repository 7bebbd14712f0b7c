#include "maintenance/level_compare.h"

#include "blobs/blob_store.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapstate {

double level_distance(std::span<const double> u, std::span<const double> h,
                      std::span<const double> u_other, std::span<const double> h_other,
                      const LevelTolerances& tolerances) {
  if (u.size() != u_other.size() || h.size() != h_other.size()) {
    return std::numeric_limits<double>::infinity();
  }
  double du = 0;
  for (std::size_t i = 0; i < u.size(); ++i) du = std::max(du, std::abs(u[i] - u_other[i]));
  double dh2 = 0;
  for (std::size_t i = 0; i < h.size(); ++i) dh2 += (h[i] - h_other[i]) * (h[i] - h_other[i]);
  return std::max(du / tolerances.displacement, std::sqrt(dh2) / tolerances.force);
}

bool forces_prove_distinct(const Configuration& a, const Configuration& b, std::size_t h_length,
                           const LevelTolerances& tolerances) {
  double df2 = 0;
  for (int k = 0; k < 3; ++k) df2 += (a.force[k] - b.force[k]) * (a.force[k] - b.force[k]);
  const double bound = std::sqrt(static_cast<double>(std::max<std::size_t>(h_length, 1))) *
                       tolerances.force;
  return std::sqrt(df2) > bound * (1 + 1e-12);
}

bool summaries_prove_distinct(const Configuration& a, const Configuration& b,
                              const LevelTolerances& tolerances) {
  if (a.summary.empty() || a.summary.size() != b.summary.size()) return false;
  double ds = 0;
  for (std::size_t i = 0; i < a.summary.size(); ++i) ds = std::max(ds, std::abs(a.summary[i] - b.summary[i]));
  return ds > tolerances.displacement * (1 + 1e-12);
}

LevelVectors read_level_vectors(const BlobStore& blobs, const Configuration& c) {
  LevelVectors v;
  if (!c.blob) return v;
  v.u = blobs.read(c.blob->segment, c.blob->name + "/u");
  v.h = blobs.read(c.blob->segment, c.blob->name + "/h");
  return v;
}

double level_distance(const LevelVectors& a, const LevelVectors& b,
                      const LevelTolerances& tolerances) {
  const auto zeros_like = [](const std::vector<double>& own, const std::vector<double>& other) {
    return own.empty() && !other.empty() ? std::vector<double>(other.size(), 0.0) : own;
  };
  const std::vector<double> ua = zeros_like(a.u, b.u), ub = zeros_like(b.u, a.u);
  const std::vector<double> ha = zeros_like(a.h, b.h), hb = zeros_like(b.h, a.h);
  return level_distance(ua, ha, ub, hb, tolerances);
}

}  // namespace hapstate
