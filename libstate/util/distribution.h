// Summary of a sample of timings (hapstate-play's report, the playback benchmark).
#pragma once

#include <span>

namespace hapstate {

struct Distribution {
  double median = 0, p99 = 0, p999 = 0, max = 0;  // nearest-rank percentiles
};

// Sorts `values` in place. All zero for an empty sample.
Distribution summarize(std::span<double> values);

}  // namespace hapstate
