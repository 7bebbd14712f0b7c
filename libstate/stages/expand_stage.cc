#include "stages/expand_stage.h"

#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "catalogue/transaction.h"
#include "statedir/stage_context.h"
#include "statedir/stage_run.h"
#include "statespace/batch_decision.h"
#include "statespace/expand_batch.h"
#include "statespace/expansion_eta.h"
#include "statespace/level_match.h"
#include "statespace/probe_model.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/stop_request.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <map>
#include <set>
#include <unordered_map>

namespace hapstate {
namespace {

using SteadyClock = std::chrono::steady_clock;

double norm3(const std::array<double, 3>& f) {
  return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
}

// Check-points configurations are computed at (contact: kFree ones too).
bool is_workspace(CheckpointClass c) {
  return c == CheckpointClass::kWorkspace || c == CheckpointClass::kFree;
}

struct GridIndexOf {
  std::map<GridIndex, Checkpoint> by_ijk;
  std::unordered_map<CheckpointId, GridIndex> ijk_of;
};

void add_counts(const BatchCounts& n, ExpandReport* r) {
  r->decided += n.decided;
  r->solved += n.solved;
  r->trivial += n.trivial;
  r->failed += n.failed;
  r->factorisations += n.factorisations;
  r->outside += n.outside;
  r->new_configurations += n.new_configurations;
  r->reused_levels += n.reused_levels;
}

// Everything the batches share.
class Expander {
 public:
  Expander(StageContext& ctx, const ExpandOptions& options)
      : ctx_(ctx),
        options_(options),
        blobs_(ctx.dir.blobs()),
        probe_(make_probe_model(ctx.problem)),
        sketch_(ctx.problem),
        tolerances_(level_tolerances(ctx.scene)),
        max_force_(ctx.scene.probe.max_force) {
    num_probe_nodes_ =
        std::max<int>(1, static_cast<int>(ctx.problem.constraints.probe_nodes.size()));
    rest_u_ = rest_displacements(ctx.problem);
    for (const Checkpoint& c : ctx.catalogue.read_all_checkpoints()) {
      grid_.by_ijk.emplace(c.ijk, c);
      grid_.ijk_of.emplace(c.id, c.ijk);
    }
  }

  BlobStore& blobs() { return blobs_; }
  const LevelTolerances& tolerances() const { return tolerances_; }

  // Throws InputError naming the configuration if a referenced segment or vector is unusable.
  void validate_blobs() {
    Catalogue& cat = ctx_.catalogue;
    for (SegmentId s : cat.referenced_segments()) {
      try {
        blobs_.provenance(s);
      } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (referenced by " + cat.file().string() +
                         "; the state directory is damaged)");
      }
    }
    for (const Configuration& c : cat.read_all_configurations()) {
      if (!c.blob || c.status == ConfigStatus::kMerged) continue;
      for (const BlobVector v : {BlobVector::kU, BlobVector::kT, BlobVector::kH,
                                 BlobVector::kTouched, BlobVector::kMultipliers}) {
        if (v == BlobVector::kTouched && !probe_->stores_touched()) continue;
        if (v == BlobVector::kMultipliers && !probe_->layout().multipliers) continue;
        if (!blobs_.contains(c.blob->segment, c.blob->dataset(v))) {
          throw InputError((blobs_.directory() / segment_file_name(c.blob->segment)).string() +
                           ": vector '" + c.blob->dataset(v) + "' of configuration " +
                           std::to_string(c.id.value()) +
                           " is missing (the state directory is "
                           "damaged)");
        }
      }
    }
  }

  // Configurations whose expandable flag disagrees with max_force and the workspace.
  std::vector<std::pair<ConfigId, bool>> expandable_changes() {
    std::vector<std::pair<ConfigId, bool>> out;
    for (const Configuration& c : ctx_.catalogue.read_all_configurations()) {
      if (c.status != ConfigStatus::kOpen) continue;
      const bool want = is_expandable(c.checkpoint, c.force);
      if (want != c.expandable) out.emplace_back(c.id, want);
    }
    return out;
  }

  bool is_expandable(CheckpointId checkpoint, const std::array<double, 3>& force) const {
    const auto it = grid_.ijk_of.find(checkpoint);
    if (it == grid_.ijk_of.end()) return false;
    return is_workspace(grid_.by_ijk.at(it->second).classification) && norm3(force) <= max_force_;
  }

  // The lowest wave with open expandable configurations, if any.
  std::optional<int> next_wave() {
    const auto max_wave = ctx_.catalogue.max_wave();
    if (!max_wave) return std::nullopt;
    for (int w = 0; w <= *max_wave; ++w)
      if (!ctx_.catalogue.frontier(w).empty()) return w;
    return std::nullopt;
  }

  // An estimate of the transitions still to decide after wave `w`, for the progress line:
  // 26 x later_configurations (expansion_eta.h) of the open configurations of later waves,
  // the workspace check-points no configuration has reached yet, the expandable configurations
  // per reached check-point so far, and the current wave's size.
  long long estimate_later(int w, long long current_wave_configurations) {
    std::set<CheckpointId> reached;
    long long expandable = 0, later = 0;
    for (const Configuration& c : ctx_.catalogue.read_all_configurations()) {
      if (c.status == ConfigStatus::kMerged) continue;
      reached.insert(c.checkpoint);
      if (!c.expandable) continue;
      ++expandable;
      if (c.status == ConfigStatus::kOpen && c.wave > w) ++later;
    }
    long long unreached = 0;
    for (const auto& [ijk, c] : grid_.by_ijk)
      if (is_workspace(c.classification) && !reached.count(c.id)) ++unreached;
    const double per_checkpoint = reached.empty() ? 1.0 : double(expandable) / reached.size();
    return Direction::kCount *
           later_configurations(w, later, unreached, per_checkpoint, current_wave_configurations);
  }

  // Undecided (source, direction) pairs of wave w, canonical order; sources with nothing left
  // undecided are returned in `complete`.
  std::vector<TransitionTask> tasks_of_wave(int w, std::vector<ConfigId>* complete) {
    std::vector<TransitionTask> tasks;
    for (const Configuration& c : ctx_.catalogue.frontier(w)) {
      bool decided[Direction::kCount] = {};
      int count = 0;
      for (const Transition& t : ctx_.catalogue.transitions_of(c.id)) {
        decided[t.direction.index()] = true;
        ++count;
      }
      decided_before_[c.id] = count;
      if (count == Direction::kCount) {
        complete->push_back(c.id);
        continue;
      }
      const GridIndex ijk = grid_.ijk_of.at(c.checkpoint);
      for (int d = 0; d < Direction::kCount; ++d) {
        if (decided[d]) continue;
        TransitionTask task;
        task.source = c;
        task.direction = Direction(d);
        const auto off = task.direction.offset();
        const GridIndex to{ijk[0] + off[0], ijk[1] + off[1], ijk[2] + off[2]};
        task.from = ctx_.grid.position(ijk);
        task.to = ctx_.grid.position(to);
        const auto it = grid_.by_ijk.find(to);
        if (it != grid_.by_ijk.end() && is_workspace(it->second.classification))
          task.target = it->second.id;
        tasks.push_back(std::move(task));
      }
    }
    return tasks;
  }

  // Decides one solved batch (canonical order, batch_decision.h), stores it (the new
  // configurations' stiffness from the engine, their vectors in a new segment closed before
  // the one transaction that references it) and commits.
  void commit_batch(const std::vector<TransitionTask>& tasks,
                    const std::vector<TransitionSolve>& solves, TransitionEngine& solver,
                    ExpandReport* report) {
    Catalogue& cat = ctx_.catalogue;
    DecideSettings settings;
    settings.sketch = &sketch_;
    settings.tolerances = tolerances_;
    settings.bound_by_touched = probe_->stores_touched();
    settings.num_probe_nodes = num_probe_nodes_;
    settings.expandable = [this](CheckpointId c, const std::array<double, 3>& f) {
      return is_expandable(c, f);
    };
    settings.next_id = ConfigId(std::max<std::int64_t>(cat.max_config_id().value(), 0) + 1);
    settings.segment = blobs_.next_segment_id();
    CatalogueLevels stored(*this);
    BatchDecision decision = decide_batch(tasks, solves, stored, settings);
    add_counts(decision.counts, report);

    // The new configurations' haptic stiffness (the transition that reached one is charged
    // its factorisation).
    std::vector<StiffnessTask> stiffness_tasks;
    for (const NewConfiguration& n : decision.fresh)
      stiffness_tasks.push_back({n.vectors, n.position});
    const std::vector<StiffnessResult> stiffness = solver.stiffnesses(stiffness_tasks);
    for (std::size_t k = 0; k < decision.fresh.size(); ++k) {
      decision.fresh[k].config.stiffness = stiffness[k].stiffness;
      decision.transitions[decision.fresh[k].transition].factorisations +=
          stiffness[k].factorisations;
      report->factorisations += stiffness[k].factorisations;
    }

    // Vectors first, durable, then the rows that reference them.
    const bool midpoints =
        std::any_of(decision.transitions.begin(), decision.transitions.end(),
                    [](const Transition& t) { return t.midpoint_blob.has_value(); });
    if (!decision.fresh.empty() || midpoints) {
      SegmentWriter writer(blobs_.directory(), settings.segment,
                           SegmentProvenance{ctx_.scene_record.hash.hex(), "", "expand"});
      for (std::size_t k = 0; k < decision.fresh.size(); ++k) {
        const NewConfiguration& n = decision.fresh[k];
        write_config_vectors(writer, *n.config.blob, *n.vectors, stiffness[k].du_dp,
                             probe_->layout());
      }
      for (std::size_t k = 0; k < decision.transitions.size(); ++k) {
        const Transition& t = decision.transitions[k];
        if (t.midpoint_blob)
          write_midpoint_vectors(writer, *t.midpoint_blob, solves[k].midpoint_u,
                                 solves[k].midpoint_du_dp);
      }
      writer.close();
    }
    Transaction tx(cat);
    for (const NewConfiguration& n : decision.fresh) cat.insert_configuration(n.config);
    for (const Transition& t : decision.transitions) cat.insert_transition(t);
    for (const auto& [source, count] : decision.decided) {
      if (decided_before_[source] + count == Direction::kCount) {
        cat.update_configuration_status(source, ConfigStatus::kExpanded);
      }
      decided_before_[source] += count;
    }
    tx.commit();
  }

 private:
  // The stored levels as decide_batch sees them: the catalogue's rows, vectors from the blobs.
  class CatalogueLevels final : public StoredLevels {
   public:
    explicit CatalogueLevels(Expander& e) : e_(e) {}
    std::vector<Configuration> at(CheckpointId c) override {
      return e_.ctx_.catalogue.configurations_at(c);
    }
    Level next_level(CheckpointId c) override { return e_.ctx_.catalogue.next_level(c); }
    const ConfigVectors& vectors(const Configuration& c) override { return e_.cached_vectors(c); }

   private:
    Expander& e_;
  };

  const ConfigVectors& cached_vectors(const Configuration& c) {
    auto it = cache_.find(c.id);
    if (it != cache_.end()) return it->second;
    if (cache_.size() >= kMaxCached) cache_.clear();
    return cache_.emplace(c.id, load_config_vectors(blobs_, c, rest_u_, probe_->layout()))
        .first->second;
  }

  static constexpr std::size_t kMaxCached = 4096;

  StageContext& ctx_;
  const ExpandOptions& options_;
  BlobStore blobs_;
  std::unique_ptr<ProbeModel> probe_;
  LevelSketch sketch_;
  LevelTolerances tolerances_;
  double max_force_;
  int num_probe_nodes_ = 1;
  std::vector<double> rest_u_;  // the zero configuration's u
  GridIndexOf grid_;
  std::unordered_map<ConfigId, ConfigVectors> cache_;
  std::map<ConfigId, int> decided_before_;

 public:
  const ProbeModel& probe() const { return *probe_; }
};

std::string parameters_of(const ExpandOptions& o, const LevelTolerances& tol, double max_force,
                          const std::string& engine) {
  char buf[360];
  std::snprintf(buf, sizeof buf,
                "algorithm=%s threads=%d batch=%d max_transitions=%s max_seconds=%s max_force=%.9g "
                "displacement_tolerance=%.9g force_tolerance=%.9g",
                o.algorithm == SolverAlgorithm::kFast ? "fast" : "reference", o.threads,
                o.batch_size,
                o.max_transitions ? std::to_string(*o.max_transitions).c_str() : "none",
                o.max_seconds ? std::to_string(*o.max_seconds).c_str() : "none", max_force,
                tol.displacement, tol.force);
  return engine.empty() ? std::string(buf) : std::string(buf) + " " + engine;
}

std::unique_ptr<TransitionEngine> make_engine(const ExpandOptions& o, const StageContext& ctx,
                                              const ProbeModel& probe, const BlobStore& blobs) {
  if (o.engine) return o.engine(ctx, probe, blobs);
  return std::make_unique<TransitionSolver>(
      ctx.problem, probe,
      blob_source_loader(blobs, rest_displacements(ctx.problem), probe.layout()), o.threads,
      o.algorithm);
}

}  // namespace

void ExpandOptions::check() const {
  if (state.empty()) throw InputError("--state: no state directory given");
  if (threads < 1) throw InputError("--threads must be >= 1 (got " + std::to_string(threads) + ")");
  if (batch_size < 1)
    throw InputError("--batch must be >= 1 (got " + std::to_string(batch_size) + ")");
  if (max_transitions && *max_transitions < 1)
    throw InputError("--max-transitions must be >= 1 (got " + std::to_string(*max_transitions) +
                     ")");
  if (max_seconds && !(*max_seconds > 0))
    throw InputError("--max-seconds must be > 0 (got " + std::to_string(*max_seconds) + ")");
}

namespace {

// The waves of one run, batch by batch, until none is left or a limit (the options' or a stop
// request) is reached; returns whether one was. One progress line for the whole expansion, its
// total re-estimated at each wave.
bool expand_waves(const ExpandOptions& options, SteadyClock::time_point start, Catalogue& cat,
                  Expander& expander, TransitionEngine& solver, ExpandReport& report) {
  bool stopped = false;
  auto limit_reached = [&] {
    if (StageRunFrame::stop(report)) return true;
    if (options.max_transitions && report.decided >= *options.max_transitions) return true;
    return options.max_seconds &&
           std::chrono::duration<double>(SteadyClock::now() - start).count() >=
               *options.max_seconds;
  };
  const long long decided_before = cat.num_transitions();
  if (options.progress && decided_before > 0)
    std::fprintf(options.progress,
                 "hapstate-expand: resuming: %lld transitions were decided by earlier runs\n",
                 decided_before);
  Progress progress("hapstate-expand: transitions", 0, options.progress);
  ExpansionEta eta;
  progress.set_resumed(decided_before);
  while (!stopped) {
    auto eta_mark = SteadyClock::now();
    const std::optional<int> wave = expander.next_wave();
    if (!wave) break;
    std::vector<ConfigId> complete;
    const std::vector<TransitionTask> tasks = expander.tasks_of_wave(*wave, &complete);
    solver.start_wave(tasks);
    if (!complete.empty()) {
      Transaction tx(cat);
      for (ConfigId id : complete) cat.update_configuration_status(id, ConfigStatus::kExpanded);
      tx.commit();
    }
    // The wave's configurations: its tasks' sources (a resumed wave has fewer tasks).
    std::set<ConfigId> sources;
    for (const TransitionTask& t : tasks) sources.insert(t.source.id);
    const long long wave_tasks = static_cast<long long>(tasks.size());
    const long long later_tasks =
        options.progress ? expander.estimate_later(*wave, static_cast<long long>(sources.size()))
                         : 0;
    const auto update_eta = [&](long long current_left) {
      progress.set_eta(
          eta.seconds_left(*wave, current_left, later_tasks,
                           Direction::kCount * std::max<long long>(1, sources.size())));
    };
    // A wave some of whose directions earlier runs decided (a resumed run's first): its cost
    // per transition, set-up included, is not one of a whole wave.
    if (!complete.empty() ||
        wave_tasks < Direction::kCount * static_cast<long long>(sources.size()))
      eta.mark_partial(*wave);
    if (options.progress) {
      progress.set_total(decided_before + report.decided + wave_tasks + later_tasks, true);
      progress.set_note("expanding wave " + std::to_string(*wave));
      update_eta(wave_tasks);
    }
    for (std::size_t b = 0; b < tasks.size(); b += options.batch_size) {
      if (limit_reached()) {
        stopped = true;
        break;
      }
      const std::size_t e = std::min(tasks.size(), b + options.batch_size);
      const std::vector<TransitionTask> batch(tasks.begin() + b, tasks.begin() + e);
      const auto solve_start = SteadyClock::now();
      // Solving ahead is worth it up to where a --max-transitions limit ends the run.
      std::size_t ahead_end = tasks.size();
      if (options.max_transitions) {
        const long long left = std::max(0LL, *options.max_transitions - report.decided);
        const long long batches = (left + options.batch_size - 1) / options.batch_size;
        ahead_end = std::min<std::size_t>(
            tasks.size(), b + static_cast<std::size_t>(batches * options.batch_size));
      }
      const std::vector<TransitionSolve> solves = solver.solve_range(b, e, ahead_end);
      const auto store_start = SteadyClock::now();
      expander.commit_batch(batch, solves, solver, &report);
      report.solve_wall_s += std::chrono::duration<double>(store_start - solve_start).count();
      report.store_wall_s +=
          std::chrono::duration<double>(SteadyClock::now() - store_start).count();
      // The wall time since the last batch (or the wave's start): the wave's set-up counted.
      const auto batch_end = SteadyClock::now();
      eta.record(*wave, static_cast<long long>(batch.size()),
                 std::chrono::duration<double>(batch_end - eta_mark).count());
      eta_mark = batch_end;
      if (options.progress) update_eta(wave_tasks - static_cast<long long>(e));
      progress.update(decided_before + report.decided, report.failed);
    }
  }
  if (options.progress) {
    if (!stopped) progress.set_total(decided_before + report.decided, false);
    progress.set_note(stopped ? "stopped" : "complete");
    progress.finish();
  }
  return stopped;
}

// The run's one line: how it ended and what it decided.
std::string expand_message(const ExpandReport& report, bool stopped, Catalogue& cat) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%s: %lld transitions decided (%lld solved, %lld failed, %lld outside the "
                "grid), %lld new configurations, %lld arrived at a state already stored; now %lld "
                "configurations, %lld transitions",
                report.stopped_by_signal ? "stopped (Ctrl-C or SIGTERM; run again to resume)"
                : stopped                ? "partial (a limit was reached; run again to continue)"
                                         : "complete",
                report.decided, report.solved, report.failed, report.outside,
                report.new_configurations, report.reused_levels,
                static_cast<long long>(cat.num_configurations()),
                static_cast<long long>(cat.num_transitions()));
  return buf;
}

}  // namespace

ExpandReport run_expand(const ExpandOptions& options) {
  options.check();
  const auto start = SteadyClock::now();
  StageContext ctx = open_stage_context(options.state);
  Catalogue& cat = ctx.catalogue;
  const StageRun grid_run = require_stage_run(cat, ctx.dir, "grid");
  if (run_input(grid_run, "grid") != ctx.grid.hash() ||
      run_input(grid_run, "problem") != ctx.problem_hash) {
    throw InputError(ctx.dir.root.string() +
                     ": the scene's grid changed since hapstate-grid ran "
                     "(re-imported with an enlarged workspace?): run hapstate-grid first");
  }
  Expander expander(ctx, options);
  expander.validate_blobs();
  const std::unique_ptr<TransitionEngine> engine =
      make_engine(options, ctx, expander.probe(), expander.blobs());
  TransitionEngine& solver = *engine;

  ExpandReport report;
  const auto changes = expander.expandable_changes();
  const NamedHashes inputs = {
      {"grid", ctx.grid.hash()}, {"problem", ctx.problem_hash}, {"scene", ctx.scene_record.hash}};
  StageRunFrame frame(
      cat, "expand", inputs,
      parameters_of(options, expander.tolerances(), ctx.scene.probe.max_force, solver.parameters()),
      start);

  // The device limit may have changed since the last run: expandable follows max_force.
  if (!changes.empty()) {
    Transaction tx(cat);
    for (const auto& [id, flag] : changes) cat.update_configuration_expandable(id, flag);
    tx.commit();
    report.expandable_changed = static_cast<long long>(changes.size());
  }
  if (!expander.next_wave()) {
    return frame.unchanged(report,
                           "nothing to do: every expandable configuration is fully "
                           "expanded (" +
                               std::to_string(cat.num_configurations()) + " configurations, " +
                               std::to_string(cat.num_transitions()) + " transitions)");
  }

  // Resume: drop segments no row references (a crash between a segment's close and its commit);
  // the frame closes the records of runs that died (we hold the directory's lock).
  report.garbage_segments =
      expander.blobs().remove_unreferenced_segments(cat.referenced_segments()).size();
  frame.run(report, [&] {
    const bool stopped = expand_waves(options, start, cat, expander, solver, report);
    report.outcome = stopped ? StageOutcome::kPartial : StageOutcome::kOk;
    solver.finish();
    report.solver = solver.timings();
    report.engine_summary = solver.summary();
    report.message = expand_message(report, stopped, cat);
  });
  return report;
}

}  // namespace hapstate
