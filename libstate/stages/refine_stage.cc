#include "stages/refine_stage.h"

#include "blobs/blob_store.h"
#include "catalogue/transaction.h"
#include "solver/path_solver.h"
#include "statedir/config_vectors.h"
#include "statedir/stage_context.h"
#include "statedir/stage_run.h"
#include "statespace/probe_model.h"
#include "statespace/refine_indicator.h"
#include "util/error.h"
#include "util/parallel_for.h"
#include "util/progress.h"
#include "util/stop_request.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <unordered_map>

namespace hapstate {
namespace {

using SteadyClock = std::chrono::steady_clock;

std::array<int, 3> corner_offset(int c) { return {(c >> 2) & 1, (c >> 1) & 1, c & 1}; }

// A cell: its 8 corners' configurations (corner c at offset corner_offset(c)) and position.
struct Cell {
  std::array<const Configuration*, 8> corner{};
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // corner 0's check-point, mesh units
  double error = 0;                                  // the largest estimate over its moves, N
  double scale = 0;  // the largest |force| at its corners and midpoints, N
};

// A point to solve: its catalogue index (RefinementPoint::point), its steps from the cell's
// lowest corner and the steps per spacing (4, 8 or 16).
struct LatticePoint {
  int index = 0;
  std::array<int, 3> q{};
  int n = 4;
};

// The corner a lattice point is solved from: the nearest (the lower one at a tie).
int nearest_corner(const LatticePoint& p) {
  int c = 0;
  for (int a = 0; a < 3; ++a) c |= (2 * p.q[a] > p.n ? 1 : 0) << (2 - a);
  return c;
}

// Sorts points by the corner they are solved from (a worker then reloads a source state and its
// factorisation less often).
std::vector<LatticePoint> by_corner(const std::vector<LatticePoint>& all) {
  std::vector<LatticePoint> out;
  for (int c = 0; c < 8; ++c)
    for (const LatticePoint& p : all)
      if (nearest_corner(p) == c) out.push_back(p);
  return out;
}

// The points a refined cell stores at `depth` (1: the quarter-spacing lattice points with an odd
// quarter index, the others being the corners and the moves' midpoints; 2: the eighth-spacing
// ones with an odd eighth index), grouped by the corner they are solved from.
std::vector<LatticePoint> new_points(int depth) {
  const int n = depth >= 2 ? 8 : 4;
  std::vector<LatticePoint> all;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        if (i % 2 == 0 && j % 2 == 0 && k % 2 == 0) continue;
        const int index = n == 4 ? 25 * i + 5 * j + k : kEighthFirstPoint + 81 * i + 9 * j + k;
        all.push_back({index, {i, j, k}, n});
      }
  return by_corner(all);
}

// The sixteenth-spacing points (depth 3) of the flagged eighth cells (64 i + 8 j + k) with an odd
// sixteenth step, each once, but those in `have` (points a cell already has rows for).
std::vector<LatticePoint> sixteenth_points(const std::vector<int>& eighth_cells,
                                           const std::set<int>& have) {
  std::set<int> seen;
  std::vector<LatticePoint> all;
  for (const int e : eighth_cells) {
    const int lo[3] = {2 * (e / 64), 2 * (e / 8 % 8), 2 * (e % 8)};
    for (int i = lo[0]; i <= lo[0] + 2; ++i)
      for (int j = lo[1]; j <= lo[1] + 2; ++j)
        for (int k = lo[2]; k <= lo[2] + 2; ++k) {
          if (i % 2 == 0 && j % 2 == 0 && k % 2 == 0) continue;
          const int index = kSixteenthFirstPoint + 289 * i + 17 * j + k;
          if (have.count(index) || !seen.insert(index).second) continue;
          all.push_back({index, {i, j, k}, 16});
        }
  }
  return by_corner(all);
}

// Whether `upper` lies across `lower`'s upper face along axis a (0: x): the four corners on that
// face are the same configurations.
bool across_upper_face(const Cell& lower, const Cell& upper, int a) {
  const int bit = 4 >> a;
  for (int c = 0; c < 8; ++c)
    if (!(c & bit) && lower.corner[c | bit] != upper.corner[c]) return false;
  return true;
}

class Refiner {
 public:
  Refiner(StageContext& ctx, int threads)
      : ctx_(ctx),
        blobs_(ctx.dir.blobs()),
        probe_(make_probe_model(ctx.problem)),
        threads_(threads),
        rest_u_(rest_displacements(ctx.problem)) {
    for (const Checkpoint& c : ctx.catalogue.read_all_checkpoints()) checkpoints_.emplace(c.id, c);
    for (const Configuration& c : ctx.catalogue.read_all_configurations())
      if (c.status != ConfigStatus::kMerged) configurations_.emplace(c.id, c);
    for (const Transition& t : ctx.catalogue.read_all_transitions())
      transitions_.emplace(std::make_pair(t.source, t.direction.index()), t);
  }

  // Every cell whose lowest corner is a live configuration whose 7 moves with offsets >= 0
  // reached live configurations, with its estimated error.
  std::vector<Cell> cells() const {
    std::vector<Cell> out;
    const Eigen::Vector3d h = ctx_.grid.spacing;
    for (const auto& [id, c0] : configurations_) {
      Cell cell;
      cell.corner[0] = &c0;
      bool complete = true;
      for (int c = 1; c < 8; ++c) {
        cell.corner[c] = target(c0.id, corner_offset(c));
        complete = complete && cell.corner[c];
      }
      if (!complete) continue;
      cell.origin = position(c0);
      for_each_recorded_move(cell, [&](int c, int d, const Transition& t) {
        const Configuration* from = cell.corner[c];
        const Configuration* to = cell.corner[c | d];
        const auto e = corner_offset(d);
        const Eigen::Vector3d v(e[0] * h.x(), e[1] * h.y(), e[2] * h.z());
        RecordedMove move;
        const std::array<double, 9>* k[3] = {&from->stiffness, &*t.midpoint_stiffness,
                                             &to->stiffness};
        move.force[0] = from->force, move.force[1] = *t.midpoint_force, move.force[2] = to->force;
        for (int n = 0; n < 3; ++n)
          for (int r = 0; r < 3; ++r)
            move.slope[n][r] =
                (*k[n])[3 * r] * v.x() + (*k[n])[3 * r + 1] * v.y() + (*k[n])[3 * r + 2] * v.z();
        cell.error = std::max(cell.error, half_spacing_error(move));
        for (const auto& f : move.force)
          cell.scale = std::max(cell.scale, std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
      });
      out.push_back(cell);
    }
    return out;
  }

  // The force and stiffness at the 729 points of `cell`'s eighth-spacing lattice (81 i + 9 j + k):
  // its corners', its moves' midpoints' and its refined rows' (`rows`, depths 1 and 2).
  std::vector<LatticeSample> eighth_lattice(const Cell& cell,
                                            const std::vector<const RefinementPoint*>& rows) const {
    std::vector<LatticeSample> out(729);
    auto put = [&](int i, int j, int k, const std::array<double, 3>& f,
                   const std::array<double, 9>& K) {
      LatticeSample& s = out[std::size_t(81 * i + 9 * j + k)];
      s.force = f, s.stiffness = K, s.known = true;
    };
    for (int c = 0; c < 8; ++c) {
      const auto o = corner_offset(c);
      put(8 * o[0], 8 * o[1], 8 * o[2], cell.corner[c]->force, cell.corner[c]->stiffness);
    }
    for_each_recorded_move(cell, [&](int c, int d, const Transition& t) {
      const auto o = corner_offset(c), e = corner_offset(d);
      put(8 * o[0] + 4 * e[0], 8 * o[1] + 4 * e[1], 8 * o[2] + 4 * e[2], *t.midpoint_force,
          *t.midpoint_stiffness);
    });
    for (const RefinementPoint* r : rows) {
      if (!r->reached) continue;
      if (r->point < kEighthFirstPoint) {
        const int q = r->point;
        put(2 * (q / 25), 2 * (q / 5 % 5), 2 * (q % 5), r->force, r->stiffness);
      } else if (r->point < kSixteenthFirstPoint) {
        const int q = r->point - kEighthFirstPoint;
        put(q / 81, q / 9 % 9, q % 9, r->force, r->stiffness);
      }
    }
    return out;
  }

  // Solves `points` of `cell` in parallel, each from its nearest corner.
  std::vector<RefinementPoint> solve(const Cell& cell, const std::vector<LatticePoint>& points) {
    std::vector<RefinementPoint> out(points.size());
    const Eigen::Vector3d h = ctx_.grid.spacing;
    if (solvers_.empty()) solvers_.resize(threads_), loaded_.resize(threads_);
    parallel_for(points.size(), threads_, [&](std::size_t n, int worker) {
      if (!solvers_[worker]) solvers_[worker] = std::make_unique<PathSolver>(ctx_.problem);
      PathSolver& solver = *solvers_[worker];
      const LatticePoint& p = points[n];
      const int c = nearest_corner(p);
      const auto o = corner_offset(c);
      Eigen::Vector3d from = cell.origin, to = cell.origin;
      for (int a = 0; a < 3; ++a) from[a] += o[a] * h[a], to[a] += p.q[a] * h[a] / p.n;
      probe_->set_state(solver, vectors(worker, *cell.corner[c]), from);
      const MoveResult move = probe_->move_to(solver, to);
      RefinementPoint& r = out[n];
      r.cell = cell.corner[0]->id;
      r.point = p.index;
      r.newton_iterations = move.iterations;
      r.wall_ms = move.wall_ms;
      if (!move.ok) {
        r.failure_reason = move.reason;
        return;
      }
      const Eigen::Vector3d f = solver.force_felt();
      const Eigen::Matrix3d k = solver.haptic_stiffness();
      if (!f.allFinite() || !k.allFinite()) {
        r.failure_reason = "the force or the stiffness at the point is not finite";
        return;
      }
      r.reached = true;
      r.force = {f.x(), f.y(), f.z()};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.stiffness[3 * i + j] = k(i, j);
    });
    return out;
  }

 private:
  // Calls fn(c, d, t) for each of the 19 moves inside `cell` that reached the cell's corner and
  // recorded its midpoint: from corner c along direction d (offsets >= 0, staying in the cell) to
  // corner c | d, by transition t.
  template <class Fn>
  void for_each_recorded_move(const Cell& cell, Fn&& fn) const {
    for (int c = 0; c < 8; ++c)
      for (int d = 1; d < 8; ++d) {
        const auto o = corner_offset(c), e = corner_offset(d);
        if ((o[0] && e[0]) || (o[1] && e[1]) || (o[2] && e[2])) continue;
        const Transition* t = transition(cell.corner[c]->id, e);
        if (!t || t->target != cell.corner[c | d]->id || !t->midpoint_force ||
            !t->midpoint_stiffness)
          continue;
        fn(c, d, *t);
      }
  }
  const Transition* transition(ConfigId source, const std::array<int, 3>& o) const {
    const auto it = transitions_.find({source, Direction::from_offset(o[0], o[1], o[2]).index()});
    return it == transitions_.end() ? nullptr : &it->second;
  }
  const Configuration* target(ConfigId source, const std::array<int, 3>& o) const {
    const Transition* t = transition(source, o);
    if (!t || t->outcome != TransitionOutcome::kReached) return nullptr;
    const auto it = configurations_.find(t->target);
    return it == configurations_.end() ? nullptr : &it->second;
  }
  Eigen::Vector3d position(const Configuration& c) const {
    const auto& p = checkpoints_.at(c.checkpoint).position;
    return {p[0], p[1], p[2]};
  }
  const ConfigVectors& vectors(int worker, const Configuration& c) {
    std::optional<std::pair<ConfigId, ConfigVectors>>& slot = loaded_[worker];
    if (!slot || slot->first != c.id)
      slot.emplace(c.id, load_config_vectors(blobs_, c, rest_u_, probe_->layout()));
    return slot->second;
  }

  StageContext& ctx_;
  BlobStore blobs_;
  std::unique_ptr<ProbeModel> probe_;
  int threads_;
  std::vector<double> rest_u_;  // the zero configuration's u
  std::unordered_map<CheckpointId, Checkpoint> checkpoints_;
  std::map<ConfigId, Configuration> configurations_;
  std::map<std::pair<ConfigId, int>, Transition> transitions_;
  std::vector<std::unique_ptr<PathSolver>> solvers_;
  std::vector<std::optional<std::pair<ConfigId, ConfigVectors>>> loaded_;
};

}  // namespace

int default_refine_depth(double radius, double spacing) {
  if (!(radius > 0)) return 1;
  return spacing > kDeeperRefineRatio * radius ? 3 : spacing > kDeepRefineRatio * radius ? 2 : 1;
}

std::string contact_spacing_note(double radius, double spacing) {
  if (!(radius > 0) || spacing <= kMeasuredSpacingRatio * radius) return "";
  char text[512];
  std::snprintf(
      text, sizeof text,
      "note: the grid spacing is %.2g x probe.radius; contact playback was measured "
      "within Hermite 1.5 %% and trilinear 3 %% of the force up to %.1f x (refined to depth "
      "3; at 1.7 x Hermite reached 4.5 %%): a smaller grid.spacing or a larger "
      "probe.radius is more accurate (docs/scene.md, \"Choosing the spacing for a contact probe\")",
      spacing / radius, kMeasuredSpacingRatio);
  return text;
}

void RefineOptions::check() const {
  if (state.empty()) throw InputError("--state: no state directory given");
  if (threads < 1) throw InputError("--threads must be >= 1 (got " + std::to_string(threads) + ")");
  if (tolerance && !(*tolerance > 0))
    throw InputError("refinement tolerance must be > 0 (got " + std::to_string(*tolerance) + ")");
  if (depth && (*depth < 1 || *depth > 3))
    throw InputError("refinement depth must be 1, 2 or 3 (got " + std::to_string(*depth) + ")");
}

RefineReport run_refine(const RefineOptions& options) {
  options.check();
  const auto start = SteadyClock::now();
  StageContext ctx = open_stage_context(options.state);
  Catalogue& cat = ctx.catalogue;
  require_stage_run(cat, ctx.dir, "expand");
  RefineReport report;
  report.tolerance =
      options.tolerance.value_or(ctx.scene.grid.refine_tolerance.value_or(kDefaultRefineTolerance));
  const double radius = ctx.problem.contact ? ctx.problem.contact->radius : 0.0;
  report.depth = options.depth.value_or(ctx.scene.grid.refine_depth.value_or(
      default_refine_depth(radius, ctx.grid.spacing.maxCoeff())));
  const NamedHashes inputs = {{"problem", ctx.problem_hash}, {"scene", ctx.scene_record.hash}};
  char parameters[120];
  std::snprintf(parameters, sizeof parameters, "tolerance=%.6g depth=%d threads=%d",
                report.tolerance, report.depth, options.threads);
  StageRunFrame frame(cat, "refine", inputs, parameters, start);
  Refiner refiner(ctx, options.threads);
  const std::vector<LatticePoint> quarter = new_points(1), eighth = new_points(2);
  const std::set<ConfigId> done1 = cat.refined_cells(1);
  const std::set<ConfigId> done2 = report.depth >= 2 ? cat.refined_cells(2) : std::set<ConfigId>{};
  struct Work {
    Cell cell;
    std::vector<LatticePoint> points;  // the depths it lacks
  };
  std::vector<Work> pending;
  std::vector<Cell> flagged;  // the cells above the tolerance
  long long total_points = 0, done_points = 0;
  for (const Cell& cell : refiner.cells()) {
    ++report.cells;
    const double relative = cell.scale > 0 ? cell.error / cell.scale : 0.0;
    report.largest_error = std::max(report.largest_error, relative);
    const bool has1 = done1.count(cell.corner[0]->id) > 0;
    const bool has2 = report.depth < 2 || done2.count(cell.corner[0]->id) > 0;
    report.refined_before += has1;
    if (!(relative > report.tolerance)) continue;
    ++report.flagged;
    flagged.push_back(cell);
    Work work{cell, {}};
    if (!has1) work.points = quarter;
    if (!has2) work.points.insert(work.points.end(), eighth.begin(), eighth.end());
    total_points += static_cast<long long>(quarter.size());
    if (report.depth >= 2) total_points += static_cast<long long>(eighth.size());
    if (work.points.empty()) continue;
    done_points -= static_cast<long long>(work.points.size());
    pending.push_back(std::move(work));
  }
  done_points += total_points;  // flagged cells' points solved by earlier runs
  // The cells in a scrambled but fixed order (by a hash of their lowest corner's id): near a
  // contact the points beside the body cost several times those farther out, and in id order
  // they would come last, so the progress line's rate, and its ETA, would be the cheap cells'.
  // Each cell is solved from its stored corners, so the order changes no result.
  auto scrambled = [](const Cell& c) {
    std::uint64_t x = static_cast<std::uint64_t>(c.corner[0]->id.value()) + 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
  };
  auto by_scramble = [&](const Work& a, const Work& b) {
    return scrambled(a.cell) < scrambled(b.cell);
  };
  std::sort(pending.begin(), pending.end(), by_scramble);
  // Depth 3, once every flagged cell has its eighth-spacing lattice: per cell, the sixteenth-
  // spacing points of the eighth cells whose estimate from that lattice and its flagged face
  // neighbours' (flag_eighth_cells) exceeds kSixteenthToleranceFactor times the tolerance times the
  // cell's largest force, but those it has.
  bool counted_eighth = false;  // sixteenth_work has counted the eighth cells above the limit
  auto sixteenth_work = [&] {
    std::map<ConfigId, std::vector<const RefinementPoint*>> rows_of;
    const std::vector<RefinementPoint> rows = cat.read_all_refinement_points();
    for (const RefinementPoint& r : rows) rows_of[r.cell].push_back(&r);
    const std::set<ConfigId> deep = cat.refined_cells(2);
    std::vector<Work> out;
    report.eighth_flagged = 0;
    counted_eighth = true;
    // The eighth-spacing lattices of the flagged cells refined to depth 2, and which of them lie
    // across each other's faces: a run of three lattice points crossing a face reads both.
    std::vector<const Cell*> deep_cells;
    std::vector<std::vector<LatticeSample>> lattices;
    std::map<ConfigId, std::size_t> by_lowest;
    for (const Cell& cell : flagged) {
      const ConfigId id = cell.corner[0]->id;
      if (!deep.count(id)) continue;
      by_lowest.emplace(id, deep_cells.size());
      deep_cells.push_back(&cell);
      lattices.push_back(refiner.eighth_lattice(cell, rows_of[id]));
    }
    std::vector<std::array<const std::vector<LatticeSample>*, 6>> neighbours(deep_cells.size());
    for (std::size_t n = 0; n < deep_cells.size(); ++n)
      for (int a = 0; a < 3; ++a) {
        const auto it = by_lowest.find(deep_cells[n]->corner[4 >> a]->id);
        if (it == by_lowest.end() || !across_upper_face(*deep_cells[n], *deep_cells[it->second], a))
          continue;
        neighbours[n][std::size_t(2 * a + 1)] = &lattices[it->second];
        neighbours[it->second][std::size_t(2 * a)] = &lattices[n];
      }
    const std::array<double, 3> h = {ctx.grid.spacing.x(), ctx.grid.spacing.y(),
                                     ctx.grid.spacing.z()};
    for (std::size_t n = 0; n < deep_cells.size(); ++n) {
      const Cell& cell = *deep_cells[n];
      const std::vector<const RefinementPoint*>& mine = rows_of[cell.corner[0]->id];
      const std::vector<int> cells =
          flag_eighth_cells(lattice_with_halo(lattices[n], neighbours[n]), h,
                            kSixteenthToleranceFactor * report.tolerance * cell.scale);
      report.eighth_flagged += static_cast<long long>(cells.size());
      std::set<int> have;
      for (const RefinementPoint* r : mine)
        if (r->point >= kSixteenthFirstPoint) have.insert(r->point);
      Work work{cell, sixteenth_points(cells, have)};
      if (!work.points.empty()) out.push_back(std::move(work));
    }
    std::sort(out.begin(), out.end(), by_scramble);
    return out;
  };
  auto summary = [&] {
    char text[400];
    std::snprintf(text, sizeof text,
                  "%lld cells, %lld above the tolerance %.3g (estimated interpolation error / "
                  "the cell's largest force; largest %.3g), depth %d",
                  report.cells, report.flagged, report.tolerance, report.largest_error,
                  report.depth);
    std::string out = text;
    if (counted_eighth)
      out += ", " + std::to_string(report.eighth_flagged) + " eighth cells above " +
             std::to_string(kSixteenthToleranceFactor) + " x the tolerance at depth 3";
    return out;
  };
  std::vector<Work> deeper;
  if (pending.empty() && report.depth >= 3) deeper = sixteenth_work();
  if (pending.empty() && deeper.empty()) {
    return frame.unchanged(report, "nothing to do: " + summary() + ", " +
                                       std::to_string(report.refined_before) + " refined");
  }
  // Solves each work's points and commits them, a cell per transaction; false when stopped.
  auto solve_all = [&](const std::vector<Work>& works, Progress& progress, long long& done) {
    for (const Work& work : works) {
      if (StageRunFrame::stop(report)) return false;
      const std::vector<RefinementPoint> points = refiner.solve(work.cell, work.points);
      Transaction tx(cat);
      cat.insert_refinement_points(points);
      tx.commit();
      ++report.refined;
      report.points += static_cast<long long>(points.size());
      for (const RefinementPoint& p : points) report.failed += !p.reached;
      done += static_cast<long long>(points.size());
      progress.update(done, report.failed);
    }
    return true;
  };
  frame.run(report, [&] {
    bool complete = true;
    if (!pending.empty()) {
      Progress progress("hapstate-refine: points", total_points, options.progress);
      progress.set_resumed(done_points);  // flagged cells refined by earlier runs: not in the rate
      complete = solve_all(pending, progress, done_points);
      progress.set_note(complete ? "complete" : "stopped");
      progress.finish();
      if (complete && report.depth >= 3) deeper = sixteenth_work();
    }
    if (complete && !deeper.empty()) {
      long long total = 0, done = 0;
      for (const Work& work : deeper) total += static_cast<long long>(work.points.size());
      Progress progress("hapstate-refine: sixteenth-spacing points", total, options.progress);
      complete = solve_all(deeper, progress, done);
      progress.set_note(complete ? "complete" : "stopped");
      progress.finish();
    }
    report.outcome = complete ? StageOutcome::kOk : StageOutcome::kPartial;
    report.message =
        std::string(complete ? "complete" : "stopped (Ctrl-C or SIGTERM; run again to resume)") +
        ": " + summary() + "; refined " + std::to_string(report.refined) + " cells now (" +
        std::to_string(report.points) + " points, " + std::to_string(report.failed) + " failed)";
  });
  return report;
}

}  // namespace hapstate
