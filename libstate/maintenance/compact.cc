#include "maintenance/compact.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "catalogue/transaction.h"
#include "maintenance/level_merge.h"
#include "scene/scene.h"
#include "statedir/stage_run.h"
#include "statedir/stored_problem.h"
#include "statedir/stored_scene.h"
#include "util/error.h"
#include "util/text.h"

#include <algorithm>
#include <set>
#include <sstream>

namespace hapstate {
namespace {

void say(std::FILE* log, const std::string& line) {
  if (log != nullptr) std::fprintf(log, "hapstate-compact: %s\n", line.c_str());
}

Scene stored_scene(Catalogue& catalogue, const StateDir& dir, ContentHash* hash) {
  const SceneRecord record = read_stored_scene(catalogue, dir);
  *hash = record.hash;
  return parse_stored_scene(record, dir);
}

std::int64_t freelist_pages(Catalogue& catalogue) {
  const QueryResult r = catalogue.query_read_only("PRAGMA freelist_count");
  return r.rows.empty() ? 0 : std::get<std::int64_t>(r.rows.front().front());
}

// The exact bytes and, from 1 KiB, the readable size: "1273856 (1.2 MiB)".
std::string bytes_text(std::int64_t bytes) {
  return bytes >= 1024 ? std::to_string(bytes) + " (" + size_text(bytes) + ")"
                       : std::to_string(bytes);
}

std::string counts_text(const CompactReport& r) {
  std::ostringstream s;
  s << plural(r.merged_levels, "duplicate level", "duplicate levels") << " merged";
  if (r.merged_levels > 0)
    s << " (" << plural(r.retargeted_transitions, "transition", "transitions")
      << " redirected to the kept level, " << r.moved_transitions << " moved)";
  s << ", " << plural(r.repacked_configurations, "configuration", "configurations")
    << " repacked into " << plural(r.new_segments, "segment file", "segment files") << ", "
    << plural(r.garbage_segments, "unreferenced segment file", "unreferenced segment files")
    << " removed";
  return s.str();
}

// What a dry run reports: what the merges and the repack plan would do.
void report_dry_run(const std::vector<LevelMerge>& merges, const RepackPlan& plan,
                    const BlobStore& blobs, const RepackOptions& repack, CompactReport& report) {
  report.merged_levels = static_cast<std::int64_t>(merges.size());
  report.repacked_configurations =
      plan.needed ? std::count_if(plan.moves.begin(), plan.moves.end(),
                                  [](const BlobMove& m) { return m.direction < 0; })
                  : 0;
  // The segments the live configurations would reference afterwards: those the repack
  // leaves alone plus the ones it would write; byte sizes are not predicted.
  report.new_segments = count_repacked_segments(plan, blobs, repack);
  const std::set<SegmentId> emptied(plan.sources.begin(), plan.sources.end());
  std::set<SegmentId> kept;
  for (const BlobMove& m : plan.moves)
    if (!(plan.needed && emptied.contains(m.from.segment))) kept.insert(m.from.segment);
  for (const SegmentId s : plan.pinned) kept.insert(s);
  report.after = report.before;
  report.after.segments = static_cast<std::int64_t>(kept.size()) + report.new_segments;
}

// The merges and the repacked blob references, in one transaction: all or nothing.
void commit_compaction(Catalogue& catalogue, const std::vector<LevelMerge>& merges,
                       const RepackResult& repacked, CompactReport& report) {
  Transaction transaction(catalogue);
  // Midpoint references first: a merge may give a transition row to another source.
  for (const RepackResult::NewRef& r : repacked.new_refs)
    if (r.direction >= 0)
      catalogue.update_transition_midpoint_blob(r.config, Direction(r.direction), r.ref);
  const MergeCounts counts = apply_level_merges(catalogue, merges);
  for (const RepackResult::NewRef& r : repacked.new_refs)
    if (r.direction < 0) catalogue.update_configuration_blob(r.config, r.ref);
  transaction.commit();
  report.merged_levels = counts.merged_levels;
  report.retargeted_transitions = counts.retargeted_transitions;
  report.moved_transitions = counts.moved_transitions;
}

}  // namespace

std::string CompactReport::headline() const {
  if (unchanged()) return "nothing to do (" + size_text(before.total()) + " on disk)";
  return "disk " + size_text(before.total()) + " -> " + size_text(after.total()) + ": " +
         counts_text(*this);
}

std::string CompactReport::text() const {
  std::ostringstream s;
  if (unchanged()) {
    s << "nothing to do: no duplicate level, no garbage, blobs already packed (" << before.segments
      << (before.segments == 1 ? " segment; total bytes " : " segments; total bytes ")
      << bytes_text(before.total()) << ")\n";
    return s.str();
  }
  s << (dry_run ? "would do: " : "") << counts_text(*this) << "\n";
  s << "duplicate search (two levels of one check-point that are the same state): "
    << plural(compared_pairs, "pair", "pairs") << " compared vector by vector, " << bound_rejections
    << " told apart at once by their stored summaries and forces\n";
  s << "segments: " << before.segments << " -> " << after.segments << "\n";
  if (dry_run) {
    s << "bytes now: catalogue " << bytes_text(before.catalogue_bytes) << ", blobs "
      << bytes_text(before.blob_bytes) << ", total " << bytes_text(before.total())
      << " (a dry run does not predict the sizes after)\n";
    return s.str();
  }
  s << "catalogue bytes: " << bytes_text(before.catalogue_bytes) << " -> "
    << bytes_text(after.catalogue_bytes) << "\n";
  s << "blob bytes: " << bytes_text(before.blob_bytes) << " -> " << bytes_text(after.blob_bytes)
    << "\n";
  s << "total bytes: " << bytes_text(before.total()) << " -> " << bytes_text(after.total()) << "\n";
  return s.str();
}

void CompactOptions::check() const {
  if (repack.max_segment_values < 1)
    throw InputError("--segment-values must be >= 1 (got " +
                     std::to_string(repack.max_segment_values) + ")");
  if (repack.zstd_level < 1 || repack.zstd_level > 22)
    throw InputError("--zstd-level must be in 1..22 (got " + std::to_string(repack.zstd_level) +
                     ")");
}

CompactReport run_compact(const CompactOptions& options) {
  options.check();
  std::FILE* log = options.log;
  const StateDir dir = locate_state(options.state);
  std::optional<StateDirLock> lock;
  if (!options.dry_run) lock.emplace(dir);
  CompactReport report;
  report.dry_run = options.dry_run;
  report.before = measure_disk_use(dir);

  const auto hook = [&](std::string_view point) {
    if (options.fault_point) options.fault_point(point);
  };
  std::optional<Catalogue> catalogue_slot;
  catalogue_slot.emplace(dir.catalogue(),
                         options.dry_run ? OpenMode::kReadOnly : OpenMode::kMigrate);
  Catalogue& catalogue = *catalogue_slot;
  BlobStore blobs(dir.blobs());
  ContentHash scene_hash;
  const Scene scene = stored_scene(catalogue, dir, &scene_hash);
  const LevelTolerances tolerances = level_tolerances(scene);

  StageRunFrame frame(catalogue, "compact", {{"scene", scene_hash}},
                      "max_segment_values=" + std::to_string(options.repack.max_segment_values) +
                          " zstd_level=" + std::to_string(options.repack.zstd_level));
  auto work = [&] {
    // 1. Garbage left by a crash (or by an earlier compaction that died before deleting).
    const std::set<SegmentId> referenced = catalogue.referenced_segments();
    report.garbage_segments =
        static_cast<std::int64_t>(blobs.unreferenced_segments(referenced).size());
    if (!options.dry_run && report.garbage_segments > 0) {
      blobs.remove_unreferenced_segments(referenced);
      say(log, "removed " + std::to_string(report.garbage_segments) + " garbage segments");
    }

    // 2. Duplicate levels.
    MergeSearchStats stats;
    const std::vector<LevelMerge> merges = find_level_merges(
        catalogue, blobs, tolerances, stored_rest_displacements(dir, scene.mesh.unit), &stats);
    report.compared_pairs = stats.compared;
    report.bound_rejections = stats.bound_rejections;
    std::set<ConfigId> merged_ids;
    for (const LevelMerge& m : merges) merged_ids.insert(m.merged);

    // 3. Repack the vectors of the configurations that stay live.
    std::vector<Configuration> live;
    for (Configuration& c : catalogue.read_all_configurations()) {
      if (c.status != ConfigStatus::kMerged && !merged_ids.contains(c.id))
        live.push_back(std::move(c));
    }
    // Every transition row stays (a merged configuration's too), and with it its midpoint
    // vectors.
    std::vector<Transition> midpoints;
    for (Transition& t : catalogue.read_all_transitions())
      if (t.midpoint_blob) midpoints.push_back(std::move(t));
    const RepackPlan plan = plan_repack(live, midpoints, blobs, options.repack);
    report.dead_vectors = plan.dead_vectors;
    report.freelist_pages = freelist_pages(catalogue);
    const bool nothing_to_do = merges.empty() && !plan.needed && report.garbage_segments == 0 &&
                               report.freelist_pages == 0;
    report.outcome = nothing_to_do ? StageOutcome::kUnchanged : StageOutcome::kOk;

    if (options.dry_run) {  // a dry run ends here
      report_dry_run(merges, plan, blobs, options.repack, report);
      return;
    }

    RepackResult repacked;
    if (plan.needed) {
      const SegmentProvenance provenance{scene_hash.hex(), "", "compact"};
      repacked = write_repacked_segments(plan, blobs, provenance, options.repack);
      report.repacked_configurations =
          std::count_if(repacked.new_refs.begin(), repacked.new_refs.end(),
                        [](const RepackResult::NewRef& r) { return r.direction < 0; });
      report.new_segments = static_cast<std::int64_t>(repacked.new_segments.size());
      say(log, "wrote " + plural(report.new_segments, "new segment file", "new segment files"));
    }
    hook("segments-written");

    // 4. One transaction: merges and blob references, all or nothing.
    if (!merges.empty() || !repacked.new_refs.empty())
      commit_compaction(catalogue, merges, repacked, report);
    hook("committed");

    // 5. The old segments are now garbage; then VACUUM.
    blobs.remove_unreferenced_segments(catalogue.referenced_segments());
    report.message = report.unchanged() ? "nothing to do" : counts_text(report);
  };
  if (options.dry_run) {  // a dry run records no stage run
    work();
    return report;
  }
  frame.run(report, work);
  if (!report.unchanged()) catalogue.vacuum();  // after the run's end is recorded
  blobs.close_all();
  catalogue_slot.reset();  // closing the last connection folds the WAL into the file
  report.after = measure_disk_use(dir);
  return report;
}

}  // namespace hapstate
