// Repacking the live blobs of a state directory into fewer, dense segments. Crash safety
// (docs/storage.md): new segments are written and fsynced first; the caller then repoints the
// catalogue in one transaction; the old segments, now unreferenced, are garbage.
#pragma once

#include "blobs/segment.h"
#include "catalogue/records.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hapstate {

class BlobStore;

struct RepackOptions {
  // A new segment is closed once it holds this many values (float64 or float32) and the next
  // configuration would exceed it: 2^27 values = 1 GiB of float64 before compression.
  std::int64_t max_segment_values = std::int64_t{1} << 27;
  int zstd_level = 3;
};

// One blob whose vectors move: a configuration's, or the midpoint vectors of its transition
// in `direction`.
struct BlobMove {
  ConfigId config;
  int direction = -1;  // >= 0: the midpoint blob of transition (config, direction)
  BlobRef from;
  std::vector<std::string> vectors;  // full names in `from.segment`, e.g. "c42/u"
};

struct RepackPlan {
  bool needed = false;             // false: nothing is written
  std::vector<BlobMove> moves;     // by (config id, direction)
  std::vector<SegmentId> sources;  // segments emptied by the moves
  std::set<SegmentId> pinned;      // segments holding vectors that belong to no
                                   // configuration (e.g. the mesh): never repacked
  std::int64_t live_values = 0;    // values of the repackable live vectors
  std::int64_t dead_vectors = 0;   // vectors of merged or deleted configurations
};

// Decides what to repack. `live` = the configurations that keep their vectors (not merged),
// `midpoints` = the transitions whose midpoint vectors are kept (their midpoint_blob).
// In a segment referenced by either, a vector is live if it lies under a live blob name,
// dead if its top group is "c<digits>" or "m<digits>_<digits>" and it is not live, foreign
// otherwise (which pins the segment). Repacking is needed when the repackable segments hold a dead
// vector or are more than ceil(live_values / max_segment_values). Reads segment listings only.
RepackPlan plan_repack(std::span<const Configuration> live, std::span<const Transition> midpoints,
                       const BlobStore& blobs, const RepackOptions& options);

struct RepackResult {
  struct NewRef {
    ConfigId config;
    int direction = -1;  // as BlobMove
    BlobRef ref;
  };
  std::vector<NewRef> new_refs;  // as plan.moves
  std::vector<SegmentId> new_segments;
  std::int64_t values_written = 0;
};

// Copies the vectors of `plan.moves` (same names, same precision) into new segments with
// ids from blobs.next_segment_id() upwards, each closed and fsynced before this returns.
// Nothing in the catalogue changes. On an exception, the segments written so far stay on
// disk unreferenced (garbage).
// How many segments write_repacked_segments would write for `plan` (the same greedy packing,
// from the segments' listings; nothing is read or written). 0 if !plan.needed.
std::int64_t count_repacked_segments(const RepackPlan& plan, const BlobStore& blobs,
                                     const RepackOptions& options);

RepackResult write_repacked_segments(const RepackPlan& plan, const BlobStore& blobs,
                                     const SegmentProvenance& provenance,
                                     const RepackOptions& options);

}  // namespace hapstate
