#include "statespace/expansion_eta.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace hapstate {

long long later_configurations(long long later_open, long long unreached, double per_checkpoint,
                               long long current_wave_configurations) {
  if (unreached <= 0) return later_open;
  const long long needed = std::llround(per_checkpoint * static_cast<double>(unreached));
  const long long wave = std::max(1LL, current_wave_configurations);
  return later_open + (needed + wave - 1) / wave * wave;
}

void ExpansionEta::record(int wave, long long decided, double seconds) {
  if (decided <= 0) return;
  Work& w = waves_[wave];
  w.decided += decided;
  w.seconds += std::max(0.0, seconds);
}

double ExpansionEta::cost(int wave) const {
  const auto it = waves_.find(wave);
  return it == waves_.end() ? -1.0 : it->second.seconds / static_cast<double>(it->second.decided);
}

double ExpansionEta::growth(int wave) const {
  // The two latest waves measured before `wave` (complete ones: the loop finishes a wave before
  // the next starts); with fewer, no growth is known.
  auto it = waves_.lower_bound(wave);
  if (std::distance(waves_.begin(), it) < 2) return 1.0;
  const auto last = std::prev(it), before = std::prev(last);
  const double a = before->second.seconds / static_cast<double>(before->second.decided);
  const double b = last->second.seconds / static_cast<double>(last->second.decided);
  if (!(a > 0) || !(b > 0)) return 1.0;
  return std::clamp(b / a, 1.0, kMaxGrowth);
}

double ExpansionEta::seconds_left(int wave, long long current_left, long long later,
                                  long long wave_size) const {
  wave_size = std::max(1LL, wave_size);
  current_left = std::clamp(current_left, 0LL, wave_size);
  const double g = growth(wave);
  // The cost the earlier waves predict for this one: the latest one's, grown once.
  double predicted = -1;
  if (const auto it = waves_.lower_bound(wave); it != waves_.begin()) {
    const Work& last = std::prev(it)->second;
    predicted = last.seconds / static_cast<double>(last.decided) * g;
  }
  // This wave's own cost so far, trusted as it covers more of the wave: its batches differ
  // (moves into the body cost many times moves away from it or out of the grid).
  double c = cost(wave);
  if (c < 0) {
    c = predicted;
  } else if (predicted > 0) {
    const double covered = static_cast<double>(wave_size - current_left) / wave_size;
    c = covered * c + (1 - covered) * predicted;
  }
  if (c < 0) return -1.0;
  double seconds = c * static_cast<double>(current_left);
  for (long long left = std::max(0LL, later); left > 0; left -= wave_size) {
    c *= g;
    seconds += c * static_cast<double>(std::min(left, wave_size));
  }
  return seconds;
}

}  // namespace hapstate
