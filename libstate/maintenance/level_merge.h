// Finding and merging levels stored twice: two configurations at one check-point within the
// level tolerances (maintenance/level_compare.h). The lower id is kept; the other is marked
// kMerged, loses its vectors, and every reference to it is rewritten (docs/inspect.md,
// "Compaction rules").
#pragma once

#include "catalogue/records.h"
#include "scene/scene.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hapstate {

class BlobStore;
class Catalogue;

struct LevelMerge {
  ConfigId kept;        // the lowest id of its group of duplicates
  ConfigId merged;      // a duplicate of `kept`, higher id
  double distance = 0;  // level_distance(kept, merged) <= 1
};

struct MergeSearchStats {
  std::int64_t compared = 0;          // pairs whose vectors were compared
  std::int64_t bound_rejections = 0;  // pairs told apart by summaries and forces (no vector read)
};

// Every duplicate among the live (not kMerged) configurations, deterministically: per
// check-point, in id order, each configuration is compared with the representatives kept so
// far (ascending id) and merged into the first one within tolerance; otherwise it becomes a
// representative. Sorted by `merged`. Reads blobs; writes nothing. Throws InputError for a
// missing or unreadable blob.
// rest_u: the zero configurations' u (stored_rest_displacements; empty: zeros).
std::vector<LevelMerge> find_level_merges(Catalogue& catalogue, const BlobStore& blobs,
                                          const LevelTolerances& tolerances,
                                          const std::vector<double>& rest_u,
                                          MergeSearchStats* stats = nullptr);

struct MergeCounts {
  std::int64_t merged_levels = 0;
  std::int64_t retargeted_transitions = 0;  // transitions that reached a merged level
  std::int64_t moved_transitions = 0;  // a merged level's own transitions given to the kept one
};

// Applies `merges` to the catalogue; call it inside a Transaction (it is not atomic by itself).
// For each merge: transitions targeting `merged` target `kept`; the transitions of `merged` in
// directions `kept` has not decided move to `kept` (the rest stay, for the record); `merged`
// gets status kMerged and no blob; `kept` becomes kExpanded once it holds all 26 directions.
MergeCounts apply_level_merges(Catalogue& catalogue, std::span<const LevelMerge> merges);

}  // namespace hapstate
