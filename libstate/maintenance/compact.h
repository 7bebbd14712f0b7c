// The controller of hapstate-compact: merges duplicate levels, repacks the live blobs into
// fewer segments, drops garbage segments and vacuums the catalogue (docs/inspect.md,
// "Compaction rules"). A crash at any instant leaves a consistent state directory.
#pragma once

#include "maintenance/repack.h"
#include "maintenance/state_paths.h"
#include "statedir/stage_run.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace hapstate {

struct CompactOptions {
  std::filesystem::path state;  // the state directory
  std::FILE* log = nullptr;     // progress lines; nullptr: silent
  bool dry_run = false;         // find and report only: nothing is written, no stage run recorded
  RepackOptions repack;
  // Test hook, called at the named points of a real run: "segments-written" (new segments
  // durable, catalogue not yet changed) and "committed" (catalogue repointed, old segments
  // not yet deleted). Throwing from it simulates a crash there.
  std::function<void(std::string_view point)> fault_point;

  // Throws InputError naming the first option out of range (run_compact calls it first).
  void check() const;
};

// outcome: kOk, or kUnchanged when there was nothing to do.
struct CompactReport : StageReport {
  DiskUse before, after;
  std::int64_t merged_levels = 0;
  std::int64_t retargeted_transitions = 0;
  std::int64_t moved_transitions = 0;
  std::int64_t compared_pairs = 0;    // level pairs whose vectors were compared
  std::int64_t bound_rejections = 0;  // level pairs told apart by summaries and forces
  std::int64_t garbage_segments = 0;  // unreferenced segments found at the start (removed)
  std::int64_t repacked_configurations = 0;
  std::int64_t new_segments = 0;
  std::int64_t dead_vectors = 0;    // vectors of merged configurations dropped
  std::int64_t freelist_pages = 0;  // free catalogue pages before VACUUM
  bool dry_run = false;

  // Human-readable lines: counts, then bytes before -> after.
  std::string text() const;
  // One line for `hapstate run`: the disk use before -> after and what was done.
  std::string headline() const;
};

// Compacts the state directory options.state. Throws InputError for a missing state directory,
// a catalogue without a scene, a scene that does not parse, a missing or corrupt blob; the
// state is then unchanged (or changed only by a completed, consistent step). Records a stage
// run "compact" (outcome ok, or unchanged when there was nothing to do) unless dry_run.
// Holds the StateDirLock of the directory (except for a dry run), like every writing stage:
// while it runs, a stage or a second compaction on the same directory is refused.
CompactReport run_compact(const CompactOptions& options);

}  // namespace hapstate
