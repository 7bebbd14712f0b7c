#include "util/distribution.h"

#include <algorithm>
#include <cmath>

namespace hapstate {
namespace {

double nearest_rank(std::span<const double> sorted, double fraction) {
  const auto n = static_cast<double>(sorted.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(fraction * n)));
  return sorted[std::min(rank, sorted.size()) - 1];
}

}  // namespace

Distribution summarize(std::span<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  d.median = nearest_rank(values, 0.5);
  d.p99 = nearest_rank(values, 0.99);
  d.p999 = nearest_rank(values, 0.999);
  d.max = values.back();
  return d;
}

}  // namespace hapstate
