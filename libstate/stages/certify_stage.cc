#include "stages/certify_stage.h"

#include "eval/equilibria.h"
#include "eval/evaluation.h"
#include "eval/region_path.h"
#include "playback/code_id.h"
#include "playback/writer.h"
#include "statedir/stage_context.h"
#include "statedir/stage_run.h"
#include "util/distribution.h"
#include "util/error.h"
#include "util/parallel_for.h"
#include "util/progress.h"
#include "util/stop_request.h"
#include "util/text.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>

namespace hapstate {
namespace {

using SteadyClock = std::chrono::steady_clock;

// Grid index of the cell holding `p` (its lowest corner) and of the nearest check-point, both
// inside the grid.
void locate(const PlaybackFile& file, const Eigen::Vector3d& p, std::array<int, 3>* cell,
            std::array<int, 3>* nearest) {
  const auto o = file.grid_origin(), h = file.grid_spacing();
  const auto lo = file.grid_lo(), n = file.grid_dims();
  for (int a = 0; a < 3; ++a) {
    const double q = (p[a] - o[a]) / h[a];
    const int last = lo[a] + n[a] - 1;
    (*cell)[a] = std::clamp(static_cast<int>(std::floor(q)), lo[a], std::max(lo[a], last - 1));
    (*nearest)[a] = std::clamp(static_cast<int>(std::lround(q)), lo[a], last);
  }
}

// `hash`: what it was measured on (certified_hash of the file's source hash, run_certify's).
CertificatePath certificate_path(const PlaybackFile& file, const ContentHash& hash, int seed,
                                 const EvalResult& r, double wall_ms) {
  CertificatePath p;
  p.seed = seed;
  p.playback_hash = hash;
  p.steps = static_cast<int>(r.steps.size());
  // The errors' denominator: the path's largest precise force, or the device limit on a path
  // that never met a force (a contact path clear of the body), so that a force played back
  // there is not hidden as a 0 % error.
  p.max_force = r.max_exact_force > 0 ? r.max_exact_force : file.max_force();
  p.failures = failed_steps(r);
  p.wall_ms = wall_ms;
  // eval's schemes are {trilinear, Hermite}, the order of CertificateStep's arrays.
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const EvalStep& s = r.steps[k];
    CertificateStep row;
    row.step = static_cast<int>(k) + 1;
    row.probe = {s.probe.x(), s.probe.y(), s.probe.z()};
    locate(file, s.probe, &row.cell, &row.checkpoint);
    row.solved = s.solved;
    row.onset = s.contact_onset;
    row.force = s.solved ? s.exact_force.norm() : 0.0;
    // A non-finite played-back force or displacement is the worst error there is: +inf (NaN
    // would be stored as NULL and would break the ordering of the statistics).
    auto finite_or_inf = [](double v) {
      return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
    };
    for (int scheme = 0; scheme < 2; ++scheme) {
      const SchemeResult& sr = s.schemes[scheme];
      row.error[scheme] = s.solved ? finite_or_inf((sr.force - s.exact_force).norm()) : 0.0;
      row.deformation[scheme] = s.solved ? finite_or_inf(sr.deformation_error_surface) : 0.0;
    }
    p.rows.push_back(row);
  }
  return p;
}

// The Hermite cursor's force() timed call by call along the stored paths, each step cut into
// 10 positions (a device sampling the motion), a fresh cursor per path placed as eval's.
Distribution time_queries(const PlaybackFile& file, const std::vector<CertificatePath>& paths,
                          std::int64_t* queries) {
  std::vector<double> ns;
  constexpr int kPerStep = 10;
  for (int pass = 0; pass < 2; ++pass) {  // the first pass warms the caches, untimed
    for (const CertificatePath& p : paths) {
      if (p.rows.empty()) continue;
      HapticCursor cursor(file, Scheme::kHermite);
      cursor.reset(p.rows.front().probe);
      std::array<double, 3> last = p.rows.front().probe;
      for (const CertificateStep& r : p.rows) {
        for (int k = 1; k <= kPerStep; ++k) {
          std::array<double, 3> q;
          for (int a = 0; a < 3; ++a) q[a] = last[a] + (r.probe[a] - last[a]) * k / kPerStep;
          const auto t0 = SteadyClock::now();
          const Force f = cursor.force(q);
          const auto t1 = SteadyClock::now();
          if (pass == 1) ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
          (void)f;
        }
        last = r.probe;
      }
    }
  }
  *queries = static_cast<std::int64_t>(ns.size());
  return summarize(ns);
}

// The largest |eigenvalue| of a stored stiffness's symmetric part, N per mesh unit.
double largest_stiffness(const PlaybackFile& file) {
  double largest = 0.0;
  for (std::int32_t c = 0; c < file.num_configurations(); ++c) {
    const auto k = file.stiffness(c);
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) m(r, q) = k[3 * r + q];
    const Eigen::Matrix3d sym = 0.5 * (m + m.transpose());
    if (!sym.allFinite()) continue;
    const Eigen::Vector3d e = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sym).eigenvalues();
    largest = std::max(largest, e.cwiseAbs().maxCoeff());
  }
  return largest;
}

// The headline numbers into the playback file's certificate section.
void write_playback_certificate(const std::filesystem::path& file, std::uint64_t source_hash,
                                const Certificate& c) {
  playback::CertificateRecord r{};
  r.measured_source_hash = source_hash;
  r.measured_code_id = playback_code_id();
  r.paths = c.paths;
  r.steps_per_path = c.steps_per_path;
  r.steps = c.steps;
  r.failed_steps = c.failed_steps;
  for (int s = 0; s < 2; ++s) {
    r.force_error_worst[s] = c.schemes[s].worst;
    r.force_error_p99[s] = c.schemes[s].p99;
    r.force_error_worst_n[s] = c.schemes[s].worst_n;
    r.deformation_error_worst[s] = c.schemes[s].deformation_worst;
  }
  r.stiffness_n_per_mm = c.stiffness_n_per_mm;
  r.query_median_ns = c.query_median_ns;
  r.query_p999_ns = c.query_p999_ns;
  playback::write_certificate(file, r);
}

}  // namespace

namespace {

// Measures the paths of the seeds in `missing` on options.threads threads, each stored as soon as
// it is measured (a stopped run keeps them); stops early on a stop request.
void measure_paths(const PlaybackFile& file, const ContentHash& hash, StageContext& ctx,
                   const std::vector<int>& missing, const CertifyOptions& options,
                   CertifyReport& report) {
  const auto h = file.grid_spacing();
  const double step_length = 0.5 * std::min({h[0], h[1], h[2]});
  Progress progress("hapstate-certify: paths", report.paths, options.progress);
  const long long stored_before = report.paths - static_cast<long long>(missing.size());
  progress.set_resumed(stored_before);
  std::mutex mutex;  // the catalogue and the progress line
  long long failures = 0;
  parallel_for(missing.size(), options.threads, [&](std::size_t i, int) {
    if (stop_requested()) return;
    const auto t0 = SteadyClock::now();
    const ProbePath path = precomputed_random_path(file, report.steps, step_length,
                                                   static_cast<std::uint64_t>(missing[i]));
    const EvalResult r = evaluate_path(ctx.problem, file, path, nullptr);
    const double ms = std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
    const CertificatePath p = certificate_path(file, hash, missing[i], r, ms);
    std::lock_guard<std::mutex> lock(mutex);
    ctx.catalogue.insert_certificate_path(p);
    ++report.solved_now;
    failures += p.failures;
    progress.update(stored_before + report.solved_now, failures);
  });
  progress.finish();
}

// The worst steps to give two-sided solves: each scheme's worst step (the Hermite cursor's
// first) where its error is above options.check_above of its path's force, and not solved
// already.
std::vector<CertificateLocation> steps_to_check(StageContext& ctx, const ContentHash& hash,
                                                const CertifyOptions& options) {
  const Certificate c = summarise_certificate(ctx.catalogue.read_all_certificate_paths(),
                                              ctx.catalogue.read_all_certificate_equilibria(),
                                              std::nullopt, hash, false, 1);
  std::vector<CertificateLocation> out;
  for (const CertificateLocation& l : c.worst) {  // Hermite's first
    if (!(l.error > options.check_above)) continue;
    bool done = false;
    for (const CertificateLocation& o : out) done = done || (o.seed == l.seed && o.step == l.step);
    for (const CertificateEquilibria& e : c.equilibria)
      done = done || (e.seed == l.seed && e.step == l.step);
    if (!done) out.push_back(l);
  }
  return out;
}

// Two-sided solves at the worst steps (steps_to_check), the six approaches of a step on
// options.threads threads, each step's three rows stored once solved (a stopped run resumes at
// the steps not stored).
void check_worst_steps(const PlaybackFile& file, const ContentHash& hash, StageContext& ctx,
                       const CertifyOptions& options, CertifyReport& report) {
  const std::vector<CertificateLocation> todo = steps_to_check(ctx, hash, options);
  if (todo.empty()) return;
  const auto h = file.grid_spacing();
  const auto along = half_spacing_approaches(Eigen::Vector3d(h[0], h[1], h[2]));
  Progress progress("hapstate-certify: two-sided solves at the worst steps",
                    static_cast<long long>(6 * todo.size()), options.progress);
  long long done = 0;
  for (const CertificateLocation& l : todo) {
    if (stop_requested()) return;
    const auto t0 = SteadyClock::now();
    const Eigen::Vector3d point(l.probe[0], l.probe[1], l.probe[2]);
    std::array<Approach, 6> approaches;  // axis x -, x +, y -, ...
    std::mutex mutex;                    // the progress line
    parallel_for(6, options.threads, [&](std::size_t i, int) {
      const Eigen::Vector3d start = point + (i % 2 == 0 ? -1.0 : 1.0) * along[i / 2];
      approaches[i] = approach(ctx.problem, point, start, 10);
      std::lock_guard<std::mutex> lock(mutex);
      progress.update(++done, 0);
    });
    const double ms = std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
    std::vector<CertificateEquilibria> rows;
    for (int a = 0; a < 3; ++a) {
      const TwoSided r = compare(point, along[a], approaches[2 * a], approaches[2 * a + 1]);
      CertificateEquilibria e;
      e.seed = l.seed;
      e.step = l.step;
      e.axis = a;
      e.along = along[a][a];
      e.verdict = judge(r);
      if (r.minus.converged) e.force_minus = {r.minus.force[0], r.minus.force[1], r.minus.force[2]};
      if (r.plus.converged) e.force_plus = {r.plus.force[0], r.plus.force[1], r.plus.force[2]};
      e.playback_hash = hash;
      e.wall_ms = ms / 3;
      rows.push_back(e);
    }
    ctx.catalogue.insert_certificate_equilibria(rows);
    ++report.checked_now;
  }
  progress.finish();
}

// Once every path is stored: the certificate's run-wide numbers (the query's timing, the largest
// stiffness) stored with it.
void store_certificate_run(const PlaybackFile& file, StageContext& ctx, const ContentHash& hash,
                           const CertifyReport& report) {
  CertificateRun measured;
  measured.playback_hash = hash;
  measured.paths = report.paths;
  measured.steps = report.steps;
  const Distribution d =
      time_queries(file, ctx.catalogue.read_all_certificate_paths(), &measured.queries);
  measured.query_median_ns = d.median;
  measured.query_p999_ns = d.p999;
  measured.stiffness = largest_stiffness(file) / ctx.scene.mesh.unit;  // N/m
  measured.ended = std::chrono::time_point_cast<std::chrono::milliseconds>(Clock::now());
  ctx.catalogue.write_certificate(measured);
}

}  // namespace

void CertifyOptions::check() const {
  if (state.empty()) throw InputError("--state: no state directory given");
  if (paths < 0) throw InputError("--paths must be >= 1 (got " + std::to_string(paths) + ")");
  if (steps < 0 || steps == 1)
    throw InputError("--steps must be >= 2 (got " + std::to_string(steps) + ")");
  if (threads < 1) throw InputError("--threads must be >= 1 (got " + std::to_string(threads) + ")");
  if (!(check_above >= 0))
    throw InputError("--check-above must be a fraction >= 0 (got " + std::to_string(check_above) +
                     ")");
}

CertifyReport run_certify(const CertifyOptions& options) {
  options.check();
  const auto start = SteadyClock::now();
  StageContext ctx = open_stage_context(options.state);
  const std::filesystem::path playback = ctx.dir.root / "playback.bin";
  if (!std::filesystem::exists(playback))
    throw InputError(playback.string() + ": no playback file: run hapstate-index --state " +
                     ctx.dir.root.string() + " first");
  CertifyReport report;
  report.paths = options.paths > 0 ? options.paths : ctx.scene.certify.paths;
  report.steps = options.steps > 0 ? options.steps : ctx.scene.certify.steps;
  ContentHash hash;  // of the file and the playback code that measures it
  std::uint64_t source_hash = 0;
  {
    const PlaybackFile probe_file(playback);
    if (probe_file.scene_hash() != ctx.scene_record.hash.value)
      throw InputError(playback.string() + ": built from another scene than the state directory " +
                       ctx.dir.root.string() + ": run hapstate-index --state " +
                       ctx.dir.root.string());
    source_hash = probe_file.source_hash();
    hash = certified_hash(source_hash);
  }
  const std::string params = "paths=" + std::to_string(report.paths) +
                             " steps=" + std::to_string(report.steps) +
                             " threads=" + std::to_string(options.threads) +
                             " check_above=" + std::to_string(options.check_above);
  StageRunFrame frame(ctx.catalogue, "certify",
                      {{"playback", hash}, {"scene", ctx.scene_record.hash}}, params, start);
  const bool contact = ctx.scene.probe.mode == ProbeMode::kContact;

  report.stale_deleted = ctx.catalogue.delete_stale_certificate(hash, report.steps, report.paths);
  std::set<int> stored;
  for (const CertificatePath& p : ctx.catalogue.read_all_certificate_paths()) stored.insert(p.seed);
  std::vector<int> missing;
  for (int seed = 1; seed <= report.paths; ++seed)
    if (!stored.count(seed)) missing.push_back(seed);
  const auto previous = ctx.catalogue.read_certificate();
  if (missing.empty() && previous && previous->playback_hash == hash &&
      previous->paths == report.paths && previous->steps == report.steps &&
      PlaybackFile(playback).certificate() && steps_to_check(ctx, hash, options).empty()) {
    report.certificate = summarise_certificate(ctx.catalogue.read_all_certificate_paths(),
                                               ctx.catalogue.read_all_certificate_equilibria(),
                                               previous, hash, contact);
    return frame.unchanged(report, "unchanged: the certificate of " + playback.string() +
                                       " is up to date (" + plural(report.paths, "path", "paths") +
                                       ")");
  }

  frame.run(report, [&] {
    // Until this run ends, the certificate is incomplete (summary says so); the playback file
    // keeps the headline it had.
    ctx.catalogue.delete_certificate();
    {
      const PlaybackFile file(playback);
      measure_paths(file, hash, ctx, missing, options, report);
      const bool complete = report.solved_now == static_cast<int>(missing.size());
      if (complete) check_worst_steps(file, hash, ctx, options, report);
      StageRunFrame::stop(report);  // only a stop request ends it early
      if (!report.stopped_by_signal) store_certificate_run(file, ctx, hash, report);
    }  // the file unmapped before it is rewritten
    report.certificate = summarise_certificate(ctx.catalogue.read_all_certificate_paths(),
                                               ctx.catalogue.read_all_certificate_equilibria(),
                                               ctx.catalogue.read_certificate(), hash, contact);
    if (!report.stopped_by_signal)
      write_playback_certificate(playback, source_hash, report.certificate);
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s: %d of %d paths measured now (%lld stale deleted), %s given two-sided "
                  "solves",
                  report.stopped_by_signal ? "interrupted" : "certified", report.solved_now,
                  static_cast<int>(missing.size()), static_cast<long long>(report.stale_deleted),
                  plural(report.checked_now, "worst step", "worst steps").c_str());
    report.message = line;
  });
  return report;
}

}  // namespace hapstate
