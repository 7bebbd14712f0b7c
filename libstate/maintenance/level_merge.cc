#include "maintenance/level_merge.h"

#include "blobs/blob_store.h"
#include "catalogue/catalogue.h"
#include "maintenance/level_compare.h"
#include "statedir/config_vectors.h"

#include <algorithm>
#include <map>
#include <optional>

namespace hapstate {
namespace {

// A configuration with its vectors read on first need.
struct Candidate {
  Configuration config;
  std::optional<ConfigVectors> vectors;
  std::optional<std::size_t> h_length;
};

const ConfigVectors& vectors_of(Candidate& c, const BlobStore& blobs,
                                const std::vector<double>& rest_u) {
  if (!c.vectors) c.vectors = load_level_vectors(blobs, c.config, rest_u);
  return *c.vectors;
}

std::size_t h_length_of(Candidate& c, const BlobStore& blobs) {
  if (!c.h_length) {
    c.h_length = c.vectors ? c.vectors->h.size()
                 : c.config.blob
                     ? blobs.size_of(c.config.blob->segment, c.config.blob->dataset(BlobVector::kH))
                     : 0;
  }
  return *c.h_length;
}

}  // namespace

std::vector<LevelMerge> find_level_merges(Catalogue& catalogue, const BlobStore& blobs,
                                          const LevelTolerances& tolerances,
                                          const std::vector<double>& rest_u,
                                          MergeSearchStats* stats) {
  MergeSearchStats local;
  MergeSearchStats& s = stats != nullptr ? *stats : local;
  std::map<CheckpointId, std::vector<Configuration>> by_checkpoint;
  for (Configuration& c : catalogue.read_all_configurations()) {  // by id
    if (c.status != ConfigStatus::kMerged) by_checkpoint[c.checkpoint].push_back(std::move(c));
  }
  std::vector<LevelMerge> merges;
  for (auto& [checkpoint, configs] : by_checkpoint) {
    if (configs.size() < 2) continue;
    std::vector<Candidate> representatives;
    for (Configuration& config : configs) {
      Candidate candidate{std::move(config), std::nullopt, std::nullopt};
      bool merged = false;
      for (Candidate& rep : representatives) {
        const std::size_t h_length =
            std::max(h_length_of(rep, blobs), h_length_of(candidate, blobs));
        if (compaction_distance_bound(rep.config, candidate.config, h_length, tolerances) > 1.0) {
          ++s.bound_rejections;
          continue;
        }
        ++s.compared;
        const double d = compaction_level_distance(
            vectors_of(rep, blobs, rest_u), vectors_of(candidate, blobs, rest_u), tolerances);
        if (d <= 1.0) {
          merges.push_back({rep.config.id, candidate.config.id, d});
          merged = true;
          break;
        }
      }
      if (!merged) representatives.push_back(std::move(candidate));
    }
  }
  std::sort(merges.begin(), merges.end(),
            [](const LevelMerge& a, const LevelMerge& b) { return a.merged < b.merged; });
  return merges;
}

MergeCounts apply_level_merges(Catalogue& catalogue, std::span<const LevelMerge> merges) {
  MergeCounts counts;
  for (const LevelMerge& m : merges) {
    counts.retargeted_transitions += catalogue.retarget_transitions(m.merged, m.kept);
    counts.moved_transitions += catalogue.move_transitions(m.merged, m.kept);
    catalogue.update_configuration_status(m.merged, ConfigStatus::kMerged);
    catalogue.update_configuration_blob(m.merged, std::nullopt);
    ++counts.merged_levels;
    const Configuration kept = catalogue.read_configuration(m.kept);
    if (kept.status == ConfigStatus::kOpen &&
        catalogue.transitions_of(m.kept).size() == static_cast<std::size_t>(Direction::kCount)) {
      catalogue.update_configuration_status(m.kept, ConfigStatus::kExpanded);
    }
  }
  return counts;
}

}  // namespace hapstate
