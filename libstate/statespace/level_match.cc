#include "statespace/level_match.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace hapstate {

LevelSketch::LevelSketch(const Problem& problem) {
  std::vector<int> candidates;
  const auto& role = problem.constraints.role;
  for (int n = 0; n < problem.mesh.num_nodes(); ++n) {
    bool fixed = true;
    for (int c = 0; c < 3; ++c) fixed = fixed && role[3 * n + c] == DofRole::kFixed;
    if (!fixed) candidates.push_back(n);
  }
  const std::size_t count = std::min<std::size_t>(kMaxSampleNodes, candidates.size());
  for (std::size_t k = 0; k < count; ++k)
    nodes_.push_back(candidates[k * candidates.size() / count]);
}

std::vector<double> LevelSketch::summary(const std::vector<double>& u) const {
  std::vector<double> s;
  s.reserve(3 * nodes_.size());
  for (int n : nodes_)
    for (int c = 0; c < 3; ++c) s.push_back(u.empty() ? 0.0 : u[3 * n + c]);
  return s;
}

double level_distance_bound(const std::vector<double>& summary_a,
                            const std::array<double, 3>& force_a,
                            const std::vector<double>& summary_b,
                            const std::array<double, 3>& force_b, const LevelTolerances& tolerances,
                            int probe_nodes) {
  double du = 0;
  const std::size_t n = std::min(summary_a.size(), summary_b.size());
  for (std::size_t k = 0; k < n; ++k) du = std::max(du, std::abs(summary_a[k] - summary_b[k]));
  double df = 0;
  for (int c = 0; c < 3; ++c) df = std::max(df, std::abs(force_a[c] - force_b[c]));
  const double h_bound = df / std::sqrt(static_cast<double>(std::max(1, probe_nodes)));
  return std::max(du / tolerances.displacement, h_bound / tolerances.force);
}

double level_distance(const ConfigVectors& a, const ConfigVectors& b,
                      const LevelTolerances& tolerances) {
  if (a.touched != b.touched) return std::numeric_limits<double>::infinity();
  assert(a.u.size() == b.u.size() && a.h.size() == b.h.size());
  double du = 0;
  for (std::size_t k = 0; k < a.u.size(); ++k) du = std::max(du, std::abs(a.u[k] - b.u[k]));
  double dh2 = 0;
  for (std::size_t k = 0; k < a.h.size(); ++k) dh2 += (a.h[k] - b.h[k]) * (a.h[k] - b.h[k]);
  return std::max(du / tolerances.displacement, std::sqrt(dh2) / tolerances.force);
}

}  // namespace hapstate
