#include "statespace/expansion_eta.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapstate {

long long later_configurations(int wave, long long later_open, long long unreached,
                               double per_checkpoint, long long current_wave_configurations) {
  if (unreached <= 0) return later_open;
  const long long needed = std::llround(per_checkpoint * static_cast<double>(unreached));
  if (wave == 0 || current_wave_configurations <= 0) return later_open + needed;
  const long long size = current_wave_configurations;
  const long long waves = std::max(1LL, (2 * needed + size) / (2 * size));  // nearest, >= 1
  return later_open + waves * size;
}

void ExpansionEta::record(int wave, long long decided, double seconds) {
  if (decided <= 0) return;
  Work& w = waves_[wave];
  w.decided += decided;
  w.seconds += std::isfinite(seconds) ? std::max(0.0, seconds) : 0.0;
}

void ExpansionEta::mark_partial(int wave) { waves_[wave].partial = true; }

double ExpansionEta::cost(int wave) const {
  const auto it = waves_.find(wave);
  return it == waves_.end() || it->second.decided == 0
             ? -1.0
             : it->second.seconds / static_cast<double>(it->second.decided);
}

std::vector<double> ExpansionEta::earlier_costs(int wave) const {
  std::vector<double> costs;  // oldest first
  for (const auto& [w, work] : waves_)
    if (w < wave && !work.partial && work.decided > 0)
      costs.push_back(work.seconds / static_cast<double>(work.decided));
  return costs;
}

double ExpansionEta::step(int wave) const {
  // The two latest waves measured whole before `wave`, wave 0 left out: its moves start from the
  // zero configurations (free space or the rest state) and say nothing of how the fronts' cost
  // grows. With fewer, none known.
  std::vector<double> costs;
  for (const auto& [w, work] : waves_)
    if (w > 0 && w < wave && !work.partial && work.decided > 0)
      costs.push_back(work.seconds / static_cast<double>(work.decided));
  if (costs.size() < 2) return 0.0;
  const double a = costs[costs.size() - 2], b = costs.back();
  return std::clamp(b - a, 0.0, kMaxStep * b);
}

double ExpansionEta::seconds_left(int wave, long long current_left, long long later,
                                  long long wave_size) const {
  wave_size = std::max(1LL, wave_size);
  current_left = std::max(0LL, current_left);
  const double d = step(wave);
  // The cost the earlier waves predict for this one: the latest whole one's, one step more.
  const std::vector<double> earlier = earlier_costs(wave);
  const double predicted = earlier.empty() ? -1.0 : earlier.back() + d;
  // This wave's own cost so far, weighted n / (n + kPriorTransitions) after n of its
  // transitions: a few batches outweigh the prediction (a contact scene's first fronts cost
  // many times the moves between its free check-points), one batch does not (its moves differ:
  // into the body, away from it, out of the grid).
  double c = cost(wave);
  if (c < 0) {
    c = predicted;
  } else if (predicted > 0) {
    const double n = static_cast<double>(waves_.at(wave).decided);
    const double weight = n / (n + kPriorTransitions);
    c = weight * c + (1 - weight) * predicted;
  }
  if (c < 0) return -1.0;
  double seconds = c * static_cast<double>(current_left);
  for (long long left = std::max(0LL, later); left > 0; left -= wave_size) {
    c += d;
    seconds += c * static_cast<double>(std::min(left, wave_size));
  }
  return seconds;
}

}  // namespace hapstate
