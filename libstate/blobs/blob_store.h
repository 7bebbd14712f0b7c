// Read access to the blob segments of a state directory, and their garbage collection.
#pragma once

#include "blobs/segment.h"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace hapstate {

// Opens segments of one blobs directory read-only on first use and keeps up to
// `max_open_files` of them open (least recently used closed first). Every failure is an
// InputError naming the segment file and, for a vector, its name: a missing segment, a
// truncated or corrupt file, a segment whose writer never finished (no close()), a missing
// vector, an undecodable chunk. HDF5's own error stack is never printed.
// Thread-safe: one BlobStore may be shared by all threads (HDF5 calls are serialised by the
// thread-safe HDF5 library; the cache has its own lock).
class BlobStore {
 public:
  explicit BlobStore(std::filesystem::path blobs_dir, std::size_t max_open_files = 32);
  ~BlobStore();
  BlobStore(const BlobStore&) = delete;
  BlobStore& operator=(const BlobStore&) = delete;

  const std::filesystem::path& directory() const;

  // The vector `name` of segment `id`, converted to float64 / float32 from whatever type it
  // was stored as (int32 indices included).
  std::vector<double> read(SegmentId id, std::string_view name) const;
  std::vector<float> read_float32(SegmentId id, std::string_view name) const;

  // Whether segment `id` holds a vector `name` (false if it does not; a segment that cannot
  // be opened still throws).
  bool contains(SegmentId id, std::string_view name) const;

  // Number of values of vector `name`, without reading it.
  std::size_t size_of(SegmentId id, std::string_view name) const;

  // Full names of every vector of segment `id`, e.g. "c42/u", sorted.
  std::vector<std::string> list_vectors(SegmentId id) const;

  // Storage type of vector `name` (float64, float32 or int32).
  Precision precision_of(SegmentId id, std::string_view name) const;

  // The provenance root attributes of segment `id`.
  SegmentProvenance provenance(SegmentId id) const;

  // Ids of every canonical segment file in the directory, ascending. Other files are ignored.
  std::vector<SegmentId> list_segments() const;

  // The id for the next new segment: one more than the largest existing (1 if none).
  SegmentId next_segment_id() const;

  // Segment files whose id is not in `referenced`, ascending by id: garbage left by a crash
  // between a segment's close() and the commit of the catalogue rows referencing it, or by
  // compaction. Call it only while no writer of this directory is running.
  std::vector<std::filesystem::path> unreferenced_segments(
      const std::set<SegmentId>& referenced) const;

  // Deletes the unreferenced segments (closing any cached handle first) and fsyncs the
  // directory. Returns the deleted files. Throws InputError if a file cannot be removed.
  std::vector<std::filesystem::path> remove_unreferenced_segments(
      const std::set<SegmentId>& referenced);

  // Closes every cached file handle (e.g. before the files are replaced).
  void close_all() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapstate
