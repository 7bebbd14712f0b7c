#include "maintenance/repack.h"

#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"

#include <algorithm>
#include <map>
#include <memory>
#include <set>

namespace hapstate {
namespace {

// The live blob name `vector` lies under, or "" if none.
std::string owning_name(const std::string& vector, const std::set<std::string>& names) {
  for (std::size_t slash = vector.find('/'); slash != std::string::npos;
       slash = vector.find('/', slash + 1)) {
    std::string prefix = vector.substr(0, slash);
    if (names.contains(prefix)) return prefix;
  }
  return "";
}

}  // namespace

RepackPlan plan_repack(std::span<const Configuration> live, std::span<const Transition> midpoints,
                       const BlobStore& blobs, const RepackOptions& options) {
  RepackPlan plan;
  std::vector<BlobMove> owners;  // every live blob, vectors filled below
  for (const Configuration& c : live)
    if (c.blob) owners.push_back({c.id, -1, *c.blob, {}});
  for (const Transition& t : midpoints)
    if (t.midpoint_blob) owners.push_back({t.source, t.direction.index(), *t.midpoint_blob, {}});
  std::map<SegmentId, std::set<std::string>> names_in;
  for (const BlobMove& o : owners) names_in[o.from.segment].insert(o.from.name);
  std::map<std::pair<SegmentId, std::string>, std::vector<std::string>> vectors_of;
  std::int64_t dead = 0;
  for (const auto& [segment, names] : names_in) {
    std::int64_t segment_dead = 0;
    bool foreign = false;
    for (const std::string& vector : blobs.list_vectors(segment)) {
      const std::string owner = owning_name(vector, names);
      if (!owner.empty()) {
        vectors_of[{segment, owner}].push_back(vector);
      } else if (BlobRef::is_state_group(vector.substr(0, vector.find('/')))) {
        ++segment_dead;
      } else {
        foreign = true;
      }
    }
    if (foreign) {
      plan.pinned.insert(segment);
    } else {
      dead += segment_dead;
      plan.sources.push_back(segment);
    }
  }
  for (BlobMove& move : owners) {
    if (plan.pinned.contains(move.from.segment)) continue;
    move.vectors = vectors_of[{move.from.segment, move.from.name}];
    for (const std::string& v : move.vectors)
      plan.live_values += static_cast<std::int64_t>(blobs.size_of(move.from.segment, v));
    plan.moves.push_back(std::move(move));
  }
  std::sort(plan.moves.begin(), plan.moves.end(), [](const BlobMove& a, const BlobMove& b) {
    return std::make_pair(a.config, a.direction) < std::make_pair(b.config, b.direction);
  });
  plan.dead_vectors = dead;
  const std::int64_t cap = std::max<std::int64_t>(options.max_segment_values, 1);
  const auto wanted =
      static_cast<std::size_t>(std::max<std::int64_t>(1, (plan.live_values + cap - 1) / cap));
  plan.needed = !plan.sources.empty() && (dead > 0 || plan.sources.size() > wanted);
  return plan;
}

namespace {

// The packing of the repacked vectors (the writer and the dry run's count share it): per move,
// the new segment (0, 1, ...) its vectors go to, whole blobs filled greedily up to
// max_segment_values; a blob shared by several moves is copied once, with its first move
// (the others get -1). values[k]: the values move k copies.
struct Packing {
  std::vector<int> segment;
  std::vector<std::int64_t> values;
  int count = 0;
};

Packing pack(const RepackPlan& plan, const BlobStore& blobs, const RepackOptions& options) {
  Packing p;
  std::int64_t in_segment = 0;
  std::set<std::pair<SegmentId, std::string>> copied;
  for (const BlobMove& move : plan.moves) {
    std::int64_t values = 0;
    if (!copied.insert({move.from.segment, move.from.name}).second) {
      p.segment.push_back(-1);
      p.values.push_back(0);
      continue;
    }
    for (const std::string& v : move.vectors)
      values += static_cast<std::int64_t>(blobs.size_of(move.from.segment, v));
    if (p.count == 0 || (in_segment > 0 && in_segment + values > options.max_segment_values)) {
      ++p.count;
      in_segment = 0;
    }
    in_segment += values;
    p.segment.push_back(p.count - 1);
    p.values.push_back(values);
  }
  return p;
}

}  // namespace

std::int64_t count_repacked_segments(const RepackPlan& plan, const BlobStore& blobs,
                                     const RepackOptions& options) {
  return plan.needed ? pack(plan, blobs, options).count : 0;
}

RepackResult write_repacked_segments(const RepackPlan& plan, const BlobStore& blobs,
                                     const SegmentProvenance& provenance,
                                     const RepackOptions& options) {
  RepackResult result;
  if (!plan.needed) return result;
  const Packing packing = pack(plan, blobs, options);
  SegmentWriterOptions writer_options;
  writer_options.zstd_level = options.zstd_level;
  SegmentId next = blobs.next_segment_id();
  std::unique_ptr<SegmentWriter> writer;
  int current = -1;                                             // packing index of `writer`
  std::map<std::pair<SegmentId, std::string>, BlobRef> copied;  // shared blobs copied once

  const auto close_current = [&] {
    if (!writer) return;
    writer->close();
    result.new_segments.push_back(writer->id());
    writer.reset();
  };
  for (std::size_t k = 0; k < plan.moves.size(); ++k) {
    const BlobMove& move = plan.moves[k];
    const auto key = std::make_pair(move.from.segment, move.from.name);
    if (packing.segment[k] < 0) {
      result.new_refs.push_back({move.config, move.direction, copied.at(key)});
      continue;
    }
    if (packing.segment[k] != current) {
      close_current();
      writer = std::make_unique<SegmentWriter>(blobs.directory(), next, provenance, writer_options);
      next.value += 1;
      current = packing.segment[k];
    }
    for (const std::string& v : move.vectors) {
      switch (blobs.precision_of(move.from.segment, v)) {
        case Precision::kFloat32:
          writer->write(v, std::span<const float>(blobs.read_float32(move.from.segment, v)));
          break;
        case Precision::kInt32: {  // indices: exact in float64
          const std::vector<double> values = blobs.read(move.from.segment, v);
          writer->write(v, std::span<const int>(std::vector<int>(values.begin(), values.end())));
          break;
        }
        case Precision::kFloat64:
          writer->write(v, std::span<const double>(blobs.read(move.from.segment, v)));
          break;
      }
    }
    result.values_written += packing.values[k];
    const BlobRef ref{writer->id(), move.from.name};
    copied.emplace(key, ref);
    result.new_refs.push_back({move.config, move.direction, ref});
  }
  close_current();
  return result;
}

}  // namespace hapstate
