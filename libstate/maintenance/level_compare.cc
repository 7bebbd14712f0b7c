#include "maintenance/level_compare.h"

#include <algorithm>
#include <limits>

namespace hapstate {
namespace {

// `v`, or zeros of `other`'s length when `v` is empty.
std::vector<double> or_zeros(const std::vector<double>& v, const std::vector<double>& other) {
  return v.empty() ? std::vector<double>(other.size(), 0.0) : v;
}

}  // namespace

double compaction_level_distance(const ConfigVectors& a, const ConfigVectors& b,
                                 const LevelTolerances& tolerances) {
  ConfigVectors x{or_zeros(a.u, b.u), {}, or_zeros(a.h, b.h), a.touched, {}};
  ConfigVectors y{or_zeros(b.u, a.u), {}, or_zeros(b.h, a.h), b.touched, {}};
  if (x.u.size() != y.u.size() || x.h.size() != y.h.size()) {
    return std::numeric_limits<double>::infinity();
  }
  return level_distance(x, y, tolerances);
}

double compaction_distance_bound(const Configuration& a, const Configuration& b,
                                 std::size_t h_length, const LevelTolerances& tolerances) {
  const int probe_nodes = static_cast<int>(std::max<std::size_t>(h_length, 1));
  return level_distance_bound(a.summary, a.force, b.summary, b.force, tolerances, probe_nodes);
}

}  // namespace hapstate
