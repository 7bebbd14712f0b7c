// Level comparison (docs/state-space.md): two configurations at a
// check-point are the same level iff
//   distance = max(||u - u'||_inf / u_tol, ||h - h'||_2 / h_tol) <= 1
// with the scene's level tolerances. A cheap lower bound from stored fields (force and a sketch
// of u at fixed sample nodes) rules most candidates out before full vectors are loaded.
#pragma once

#include "catalogue/records.h"
#include "problem/problem.h"
#include "scene/scene.h"
#include "statedir/config_vectors.h"

#include <vector>

namespace hapstate {

class LevelSketch {
 public:
  static constexpr int kMaxSampleNodes = 16;

  // Samples up to kMaxSampleNodes nodes that are not fully fixed, evenly spread over the node
  // ids (deterministic: depends on the constraints only).
  explicit LevelSketch(const Problem& problem);

  // The summary of u: u at the sample nodes (3 per node, mesh units).
  std::vector<double> summary(const std::vector<double>& u) const;
  const std::vector<int>& nodes() const { return nodes_; }
  int summary_size() const { return 3 * static_cast<int>(nodes_.size()); }

 private:
  std::vector<int> nodes_;
};

// A lower bound of level_distance from summaries and forces (felt force = -sum of h per
// component, so |F - F'| <= sqrt(probe_nodes) ||h - h'||). > 1 means: not the same level.
double level_distance_bound(const std::vector<double>& summary_a,
                            const std::array<double, 3>& force_a,
                            const std::vector<double>& summary_b,
                            const std::array<double, 3>& force_b, const LevelTolerances& tolerances,
                            int probe_nodes);

// The exact distance; u of a and b must have equal sizes. Configurations holding different
// touched sets are never the same level (+infinity); with equal sets h have equal sizes.
double level_distance(const ConfigVectors& a, const ConfigVectors& b,
                      const LevelTolerances& tolerances);

}  // namespace hapstate
