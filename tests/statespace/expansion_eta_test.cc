// The expansion's progress model (statespace/expansion_eta.h) on a measured expansion: the
// bundled contact scene pipelines/plate, `hapstate run` on 2 threads of an otherwise idle
// 2-core machine (2026-11-27, the expansion's code as at 4dbfb8f: 260.6 s). Its six waves each
// decided 468 transitions (18 configurations x 26) in batches of 32; below, each batch's
// seconds, in the order the stage decides them, from the catalogue's transition.wall_ms
// (thread-seconds: the wall time is about half on 2 threads, which scales every figure alike):
//   sqlite3 catalogue.sqlite "SELECT c.wave, t.wall_ms FROM transition t JOIN configuration c
//                             ON c.id = t.source ORDER BY c.wave, c.id, t.direction"
// At each wave's start the catalogue held 18 configurations per earlier wave, one per
// check-point, on 81 workspace check-points: 81, 63, 45, 27, 9, 0 unreached.
// The second scene, pipelines/liver-contact (the same machine and day, 330 s), shrinks its
// fronts wave by wave at an even cost per transition; it is replayed per wave (its mean cost in
// each wave), from the same query summed per wave and the configurations per wave.
#include "statespace/expansion_eta.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

namespace hapstate {
namespace {

constexpr long long kWaveTransitions = 468, kBatch = 32, kWaveConfigurations = 18;
const std::vector<long long> kUnreached = {81, 63, 45, 27, 9, 0};
const std::vector<std::vector<double>> kBatchSeconds = {
    {0.50, 0.60, 1.02, 0.71, 0.41, 0.95, 0.95, 1.36, 0.94, 0.57, 0.72, 0.84, 0.63, 0.75, 0.20},
    {1.77, 3.03, 3.94, 2.65, 2.63, 3.20, 2.56, 2.51, 1.85, 2.45, 2.49, 1.81, 2.07, 1.99, 0.59},
    {3.48, 6.05, 7.73, 5.24, 4.41, 4.68, 5.31, 2.11, 5.85, 6.42, 5.33, 4.43, 3.23, 5.13, 1.07},
    {5.05, 8.65, 10.73, 7.02, 5.83, 6.38, 7.82, 2.77, 8.22, 8.71, 8.23, 7.96, 5.37, 8.10, 1.25},
    {6.19, 11.88, 14.69, 9.53, 6.83, 8.43, 6.92, 3.52, 10.42, 10.81, 9.62, 10.11, 6.31, 11.31,
     1.52},
    {7.68, 14.40, 16.82, 10.73, 9.25, 11.34, 9.56, 4.99, 13.43, 15.56, 13.85, 11.61, 9.02, 12.52,
     2.11}};

struct Point {
  double elapsed_fraction;  // of the whole expansion's time
  double predicted, truth;  // seconds left
};

double total_seconds() {
  double total = 0;
  for (const auto& wave : kBatchSeconds) total = std::accumulate(wave.begin(), wave.end(), total);
  return total;
}

// A measured expansion: per wave the seconds of its batches of 32 transitions, in order, its
// configurations and the workspace check-points unreached at its start.
struct Replay {
  std::vector<std::vector<double>> batches;
  std::vector<long long> configurations, unreached;
};

// Replays an expansion batch by batch and returns, after every batch, the model's seconds left
// next to the true seconds left.
std::vector<Point> replay(const Replay& r) {
  double total = 0;
  for (const auto& wave : r.batches) total = std::accumulate(wave.begin(), wave.end(), total);
  ExpansionEta eta;
  std::vector<Point> points;
  double elapsed = 0;
  for (int w = 0; w < static_cast<int>(r.batches.size()); ++w) {
    const long long size = 26 * r.configurations[w];
    const long long later =
        26 * later_configurations(w, 0, r.unreached[w], 1.0, r.configurations[w]);
    long long done = 0;
    for (double seconds : r.batches[w]) {
      const long long batch = std::min(kBatch, size - done);
      done += batch;
      elapsed += seconds;
      eta.record(w, batch, seconds);
      points.push_back(
          {elapsed / total, eta.seconds_left(w, size - done, later, size), total - elapsed});
    }
    EXPECT_EQ(done, size) << "wave " << w;
  }
  return points;
}

Replay plate() {
  return {kBatchSeconds, std::vector<long long>(6, kWaveConfigurations), kUnreached};
}

// liver-contact per wave: (transitions decided, thread-seconds), spread evenly over its batches.
Replay liver_contact() {
  const std::vector<std::pair<long long, double>> waves = {
      {83148, 58.1}, {12194, 145.3}, {11050, 137.7}, {9256, 113.3},
      {6370, 77.9},  {3952, 44.7},   {1508, 17.4},   {260, 2.6}};
  Replay r;
  r.configurations = {3198, 469, 425, 356, 245, 152, 58, 10};
  r.unreached = {1715, 1246, 821, 465, 220, 68, 10, 0};
  for (const auto& [transitions, seconds] : waves) {
    std::vector<double> batches;
    for (long long done = 0; done < transitions; done += kBatch)
      batches.push_back(seconds * std::min(kBatch, transitions - done) / transitions);
    r.batches.push_back(batches);
  }
  return r;
}

// The largest |error| between the fractions `from` and `to` of the time, and the error at
// half-way.
std::pair<double, double> errors(const std::vector<Point>& points, double from, double to) {
  double worst = 0, half = NAN;
  for (const Point& p : points) {
    const double error = (p.predicted - p.truth) / p.truth;
    if (std::isnan(half) && p.elapsed_fraction >= 0.5) half = error;
    if (p.elapsed_fraction >= from && p.elapsed_fraction <= to)
      worst = std::max(worst, std::abs(error));
  }
  return {worst, half};
}

TEST(ExpansionEta, ThePlatesEtaIsWithin30PercentAtHalfWay) {
  // Issue 42: at half-way the run's rate promised the plate's second half in ~60 % of its time.
  const auto [worst, half] = errors(replay(plate()), 0.25, 0.9);
  EXPECT_LT(std::abs(half), 0.30) << half;
  EXPECT_LT(worst, 0.30);
}

TEST(ExpansionEta, LiverContactsEtaIsWithin30PercentAtHalfWay) {
  // Fronts that shrink at an even cost: no growth to find, whole waves of varying size. In the
  // last tenth of the time the smallest waves are counted as one wave of the current size
  // (+47 % at 89 % of the time: 31 s of wall time left, 46 s promised).
  const auto [worst, half] = errors(replay(liver_contact()), 0.2, 0.85);
  EXPECT_LT(std::abs(half), 0.30) << half;
  EXPECT_LT(worst, 0.30);
}

TEST(ExpansionEta, TheFormerEstimateWasFarShortOnTheSameReplay) {
  // The replay is not one any estimate passes: the former one (the rate of the last quarter of
  // the elapsed time, for the current wave's rest + 26 per unreached check-point) is more than
  // 30 % short at half-way, as the issue saw on the live plate.
  const double half = total_seconds() / 2;
  std::vector<std::pair<double, long long>> samples;  // (elapsed, decided) after each batch
  double elapsed = 0;
  long long decided = 0;
  for (int w = 0; w < static_cast<int>(kBatchSeconds.size()); ++w) {
    long long done = 0;
    for (double seconds : kBatchSeconds[w]) {
      const long long batch = std::min(kBatch, kWaveTransitions - done);
      done += batch, decided += batch, elapsed += seconds;
      samples.emplace_back(elapsed, decided);
      if (elapsed < half) continue;
      const double window_start = 0.75 * elapsed;
      const auto first = std::find_if(samples.begin(), samples.end(),
                                      [&](const auto& s) { return s.first >= window_start; });
      const double rate = (decided - first->second) / (elapsed - first->first);
      const double left = (kWaveTransitions - done + 26.0 * kUnreached[w]) / rate;
      EXPECT_LT(left, 0.7 * (2 * half - elapsed)) << left << " s against " << 2 * half - elapsed;
      return;
    }
  }
  ADD_FAILURE() << "half-way not reached";
}

TEST(ExpansionEta, LaterConfigurationsComeInWholeWaves) {
  EXPECT_EQ(later_configurations(1, 0, 0, 1.0, 18), 0);          // all reached: nothing after
  EXPECT_EQ(later_configurations(1, 5, 0, 1.0, 18), 5);          // only the open later ones
  EXPECT_EQ(later_configurations(3, 0, 27, 1.0, 18), 36);        // 1.5 waves of 18: two
  EXPECT_EQ(later_configurations(4, 0, 9, 1.0, 18), 18);         // the plate's last wave
  EXPECT_EQ(later_configurations(3, 0, 465, 1.0, 356), 356);     // 1.3 waves: one
  EXPECT_EQ(later_configurations(4, 0, 100, 2.0, 50), 200);      // two levels per check-point
  EXPECT_EQ(later_configurations(0, 0, 1715, 1.0, 3198), 1715);  // wave 0 is no front
  EXPECT_EQ(later_configurations(2, 3, 10, 1.0, 0), 13);         // no size known: the count
}

TEST(ExpansionEta, TheStepIsMeasuredBetweenTheLastTwoWholeWavesAndBounded) {
  ExpansionEta eta;
  EXPECT_LT(eta.seconds_left(0, 100, 0, 100), 0);  // nothing measured: no estimate
  eta.record(0, 100, 1.0);                         // wave 0: 0.01 s per transition
  EXPECT_DOUBLE_EQ(eta.cost(0), 0.01);
  // Wave 1 not started: its cost is wave 0's; 100 now and 200 later in waves of 100.
  EXPECT_NEAR(eta.seconds_left(1, 100, 200, 100), 3.0, 1e-9);
  eta.record(1, 100, 10.0);            // 0.1: ten times wave 0's, which is left out
  EXPECT_DOUBLE_EQ(eta.step(2), 0.0);  // one wave after wave 0: no step known
  eta.record(2, 100, 11.0);
  EXPECT_NEAR(eta.step(3), 0.01, 1e-12);  // 0.11 - 0.1
  eta.record(3, 100, 40.0);               // a jump of 0.29 is bounded at 0.25 x 0.4
  EXPECT_NEAR(eta.step(4), ExpansionEta::kMaxStep * 0.4, 1e-12);
  eta.record(4, 64, 12.8);  // a cheaper wave (0.2 per transition): costs are not assumed to fall
  EXPECT_DOUBLE_EQ(eta.step(5), 0.0);
  // Wave 4 after 64 of its transitions, 36 left, then 150 later in waves of 100. Its cost blends
  // the prediction (wave 3's 0.4 plus the step before wave 4: 0.1) with its own 0.2, the latter
  // weighted 64 / (64 + 128); each later wave costs one step more.
  const double d = ExpansionEta::kMaxStep * 0.4;
  const double weight = 64.0 / (64.0 + ExpansionEta::kPriorTransitions);
  const double c = weight * 0.2 + (1 - weight) * (0.4 + d);
  EXPECT_NEAR(eta.seconds_left(4, 36, 150, 100), 36 * c + 100 * (c + d) + 50 * (c + 2 * d), 1e-9);
}

TEST(ExpansionEta, APartlyDecidedWaveDoesNotPredictTheNext) {
  // A resumed run's first wave: five transitions left, its set-up counted in them.
  ExpansionEta eta;
  eta.record(2, 5, 3.0);  // 0.6 s per transition, of which most is set-up
  eta.mark_partial(2);
  EXPECT_NEAR(eta.seconds_left(2, 0, 0, 26), 0.0, 1e-12);
  EXPECT_LT(eta.seconds_left(3, 100, 0, 100), 0);  // no whole wave measured: no estimate
  eta.record(3, 100, 10.0);
  EXPECT_NEAR(eta.seconds_left(3, 0, 100, 100), 10.0, 1e-9);  // its own 0.1, no step
}

TEST(ExpansionEta, AGrowingGrabGridStaysBounded) {
  // A 17^3 grab box at its wave 3: 4 570 check-points unreached, 218 configurations in the wave
  // (21 waves of that size counted against 5 real shells). With the plate's growth the
  // estimate is long, but by a few times, not by the hundreds a compounded factor gave.
  ExpansionEta eta;
  eta.record(0, 26, 0.26);
  eta.record(1, 26 * 26, 6.76);              // 0.01
  eta.record(2, 26 * 98, 26 * 98 * 0.0125);  // 0.0125: a step of 0.0025
  const long long later = 26 * later_configurations(3, 0, 4570, 1.0, 218);
  EXPECT_EQ(later, 26 * 21 * 218);
  const double left = eta.seconds_left(3, 26 * 218, later, 26 * 218);
  const double flat = 0.0125 * (26 * 218 + later);  // every wave at wave 2's cost
  EXPECT_GT(left, flat);
  EXPECT_LT(left, 5 * flat);
}

}  // namespace
}  // namespace hapstate
