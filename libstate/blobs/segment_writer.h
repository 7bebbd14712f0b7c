// Writes one new blob segment (an HDF5 file) holding many named vectors.
#pragma once

#include "blobs/segment.h"
#include "blobs/zstd_filter.h"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string_view>

namespace hapstate {

struct SegmentWriterOptions {
  int zstd_level = kDefaultZstdLevel;  // 1 (fast) .. 22 (small)
  std::size_t chunk_elements = 65536;  // HDF5 chunk length in values (512 KiB of float64)
};

// Creates blobs_dir/seg-NNNNNN.h5 (never overwrites: an existing file is an InputError) and
// writes vectors into it: the vector "<group>/<leaf>" is a row of the 2-D dataset "<leaf>"
// (one row per group; rows may be shorter than the dataset, their lengths are in the index
// written by close()), chunked one row at a time, byte-shuffled and zstd-compressed (filter
// 32015). Root attributes record the provenance. Rows are written as they come: nothing is
// held in memory but the index. Crash-safety contract: the catalogue
// may reference the segment only after close() returned. A writer destroyed without close()
// (an exception unwound past it) deletes its file. Not thread-safe: one thread per writer;
// several writers on different threads are fine.
class SegmentWriter {
 public:
  SegmentWriter(const std::filesystem::path& blobs_dir, SegmentId id,
                const SegmentProvenance& provenance, SegmentWriterOptions options = {});
  ~SegmentWriter();
  SegmentWriter(SegmentWriter&&) noexcept;
  SegmentWriter& operator=(SegmentWriter&&) noexcept;

  // Stores `values` under `name` (see is_valid_vector_name; intermediate groups are created).
  // kFloat32 converts on write (for visual data). Throws InputError if the name is invalid or
  // already written, EnvironmentError if HDF5 fails (with the OS error when HDF5 recorded
  // one); throws std::logic_error after close().
  void write(std::string_view name, std::span<const double> values,
             Precision precision = Precision::kFloat64);
  void write(std::string_view name, std::span<const float> values);
  void write(std::string_view name, std::span<const int> values);  // int32 (indices)

  // Marks the segment complete, flushes and closes it, then fsyncs the file and blobs_dir.
  // After it returns the segment survives a power cut. Throws EnvironmentError on any I/O
  // error, naming the file and, when HDF5 recorded it, the OS error (strerror: "No space left
  // on device"); the file is then deleted by the destructor, or, if only the fsync failed,
  // left for the garbage collector. Idempotent.
  void close();

  SegmentId id() const;
  const std::filesystem::path& path() const;
  std::size_t num_vectors() const;  // vectors written so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapstate
