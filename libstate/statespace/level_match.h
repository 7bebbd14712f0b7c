// Level comparison (docs/state-space.md): two configurations at a
// check-point are the same level iff
//   distance = max(||u - u'||_inf / u_tol, ||h - h'||_2 / h_tol) <= 1
// with the scene's level tolerances. A cheap lower bound from stored fields (force and a sketch
// of u at fixed sample nodes) rules most candidates out before full vectors are loaded.
#pragma once

#include "catalogue/records.h"
#include "problem/problem.h"
#include "scene/scene.h"

#include <vector>

namespace hapstate {

// The vectors of a configuration: u (3 per node, mesh units), t (probe DOFs, mesh units),
// h (reactions at the probe DOFs, N); sticking contact: touched (the nodes the sphere holds,
// ascending; their 3 DOFs each are the probe DOFs of t and h, in that order); frictionless
// contact: h is the sphere's resultant force on the body (VectorLayout below).
struct ConfigVectors {
  std::vector<double> u, t, h;
  std::vector<int> touched;
  std::vector<double> multipliers;  // frictionless contact: (triangle, N) pairs; not compared
};

// What a configuration stores besides u (ProbeModel::layout(): one definition for the loader,
// the writer and the level comparison). Grab: t and h have a value per grabbed DOF; sticking
// contact: the touched set is stored ("<blob>/touched") and t and h have 3 values per touched
// node; frictionless contact: t is empty, h the 3 components of the sphere's force on the
// body, and the contact multipliers are stored ("<blob>/multipliers") to warm-start the moves
// from the configuration (they do not define it: level comparison ignores them).
struct VectorLayout {
  bool touched = false;      // "<blob>/touched" is stored; t and h: 3 values per touched node
  int load_size = 0;         // otherwise: the values of t
  int reaction_size = 0;     // otherwise: the values of h
  bool multipliers = false;  // "<blob>/multipliers" is stored
  int t_size(std::size_t touched_nodes) const {
    return touched ? 3 * static_cast<int>(touched_nodes) : load_size;
  }
  int h_size(std::size_t touched_nodes) const {
    return touched ? 3 * static_cast<int>(touched_nodes) : reaction_size;
  }
};

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
