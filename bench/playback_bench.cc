// Playback runtime against the precise solver it replaces (docs/benchmarks.md, "Playback"):
// haptic force queries along a 1 kHz device path on the liver playback file (trilinear and
// Hermite) and with a new cell at every query, visual frames (snapshot + deform) on the liver
// surface and on a synthetic 50 653-node mesh, and one precise Newton solve of a liver transition.
// Run: build/bench/playback_bench [--benchmark_repetitions=5 ...]; HAPSTATE_PLAYBACK=file
// measures another playback file for the force queries and the liver frame.
#include "playback_fixtures.h"
#include "solver/path_solver.h"
#include "util/distribution.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace hapstate::bench {
namespace {

using Clock = std::chrono::steady_clock;

// 1 kHz device motion of ~0.2 mm per tick: 0.02 mesh units (cm) per step.
constexpr double kDeviceStep = 0.02;
constexpr int kPathSteps = 100'000;

const std::vector<std::array<double, 3>>& liver_path() {
  static const auto path = device_path(liver_playback(), kPathSteps, kDeviceStep, 20261122);
  return path;
}

// Median and p99.9 of `samples` timed calls of `call` (steady_clock around each), as counters
// "<prefix>median" and "<prefix>p99.9" in `unit` (1e9: ns, 1e6: us). The clock's own cost
// (an empty timed region) is reported as "clock_ns".
template <typename Call>
void timed_counters(benchmark::State& state, int samples, double unit, const std::string& prefix,
                    Call&& call) {
  std::vector<double> t(static_cast<std::size_t>(samples)), empty(t.size());
  for (auto& e : empty) {
    const auto t0 = Clock::now();
    const auto t1 = Clock::now();
    e = std::chrono::duration<double>(t1 - t0).count() * 1e9;
  }
  for (int k = 0; k < samples; ++k) {
    const auto t0 = Clock::now();
    call(k);
    const auto t1 = Clock::now();
    t[static_cast<std::size_t>(k)] = std::chrono::duration<double>(t1 - t0).count() * unit;
  }
  const Distribution d = summarize(t);
  state.counters[prefix + "median"] = d.median;
  state.counters[prefix + "p99.9"] = d.p999;
  state.counters["clock_ns"] = summarize(empty).median;
}

void BM_ForceQuery(benchmark::State& state, Scheme scheme) {
  const PlaybackFile& file = liver_playback();
  const auto& path = liver_path();
  HapticCursor cursor(file, scheme);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cursor.force(path[i]));
    i = i + 1 == path.size() ? 0 : i + 1;
  }
  cursor.reset();
  timed_counters(state, static_cast<int>(path.size()), 1e9, "ns_",
                 [&](int k) { benchmark::DoNotOptimize(cursor.force(path[k])); });
  state.SetLabel(std::string(scheme == Scheme::kHermite ? "hermite" : "trilinear") + ", liver " +
                 std::to_string(file.num_configurations()) + " configurations");
}

// The worst case of the haptic path: every query in another cell (two points on either side of a
// cell face near the rest position), so each call enters a cell and fits its midpoint data
// (docs/playback.md, "Between the check-points") before it interpolates.
void BM_CellEntry(benchmark::State& state, Scheme scheme) {
  const PlaybackFile& file = liver_playback();
  HapticCursor cursor(file, scheme);
  std::array<double, 3> a = file.rest_position(), b = a;
  for (int k = 0; k < 3; ++k) a[k] += 0.3 * file.grid_spacing()[k];
  b = a;
  b[0] -= 0.6 * file.grid_spacing()[0];
  const std::array<double, 3> points[2] = {a, b};
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cursor.force(points[i]));
    i ^= 1;
  }
  timed_counters(state, 20'000, 1e9, "ns_",
                 [&](int k) { benchmark::DoNotOptimize(cursor.force(points[k & 1])); });
  state.SetLabel(std::string(scheme == Scheme::kHermite ? "hermite" : "trilinear") +
                 ", a new cell every call");
}

// One frame: the snapshot of a cursor inside a cell (8 corners) and deform() with the scheme
// (Hermite: the 8 corners' displacements and slopes, 32 arrays; on half-spacing cells the
// corner's 4 and 4 per midpoint, 32 too). The point is generic in the cell and in its half cell
// (no basis vanishes).
void frame(benchmark::State& state, const PlaybackFile& file, const std::string& name,
           Scheme scheme) {
  HapticCursor cursor(file, scheme);
  std::array<double, 3> p = file.rest_position();
  for (int a = 0; a < 3; ++a) p[a] += (0.3 + 0.17 * a) * file.grid_spacing()[a];
  cursor.force(p);
  Snapshot snapshot;
  std::vector<float> positions(3 * static_cast<std::size_t>(file.num_view_nodes()));
  for (auto _ : state) {
    cursor.snapshot(&snapshot);
    deform(file, snapshot, positions);
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  const int samples = file.num_view_nodes() > 10'000 ? 300 : 20'000;
  timed_counters(state, samples, 1e6, "us_", [&](int) {
    cursor.snapshot(&snapshot);
    deform(file, snapshot, positions);
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  });
  state.SetLabel(std::string(scheme == Scheme::kHermite ? "hermite" : "trilinear") + ", " + name +
                 ", " + std::to_string(file.num_view_nodes()) + " view nodes");
}

void BM_FrameLiver(benchmark::State& state, Scheme scheme) {
  frame(state, liver_playback(), "liver surface", scheme);
}
void BM_FrameSynthetic(benchmark::State& state, Scheme scheme) {
  frame(state, synthetic_playback(), "synthetic box, all nodes", scheme);
}
void BM_FrameSyntheticMidpoints(benchmark::State& state, Scheme scheme) {
  frame(state, synthetic_midpoint_playback(), "synthetic box, all nodes, half-spacing cells",
        scheme);
}

// One precise transition as hapstate-expand solves it: the liver at rest, the probe moved to
// a face-neighbouring check-point (one grid spacing along z), the scene's sub-steps and
// Newton tolerance.
void BM_NewtonSolve(benchmark::State& state) {
  const Problem& problem = liver_problem();
  PathSolver solver(problem);
  const Eigen::Vector3d t(0.0, 0.0, liver_playback().grid_spacing()[2]);
  int iterations = 0;
  for (auto _ : state) {
    solver.reset();
    const MoveResult r = solver.move_to(t);
    if (!r.ok) state.SkipWithError(r.reason.c_str());
    iterations = r.iterations;
  }
  state.counters["newton_iterations"] = iterations;
  state.SetLabel("liver " + std::to_string(solver.num_dofs()) + " DOFs, one grid spacing");
}

BENCHMARK_CAPTURE(BM_ForceQuery, trilinear, Scheme::kTrilinear)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_ForceQuery, hermite, Scheme::kHermite)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_CellEntry, trilinear, Scheme::kTrilinear)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_CellEntry, hermite, Scheme::kHermite)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_FrameLiver, trilinear, Scheme::kTrilinear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_FrameLiver, hermite, Scheme::kHermite)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_FrameSynthetic, trilinear, Scheme::kTrilinear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_FrameSynthetic, hermite, Scheme::kHermite)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_FrameSyntheticMidpoints, hermite, Scheme::kHermite)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NewtonSolve)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hapstate::bench

BENCHMARK_MAIN();
