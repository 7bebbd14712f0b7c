// Blob segments: HDF5 files blobs/seg-NNNNNN.h5, each written once by a SegmentWriter and read
// only afterwards. Names, numbers and provenance shared by the writer, the reader and the
// garbage collector. Layout and naming rules: docs/storage.md.
#pragma once

#include <compare>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hapstate {

// Number of a segment file (>= 1); the catalogue stores it in configuration.blob_segment.
// Default-constructed = kInvalid.
struct SegmentId {
  std::int64_t value = -1;

  constexpr bool valid() const { return value >= 1; }
  friend constexpr auto operator<=>(SegmentId, SegmentId) = default;
};
inline constexpr SegmentId kInvalidSegmentId{};

// Version of the segment layout (root attribute "hapstate_segment_format"). 1: one 1-D
// dataset per vector, at its name; 2: the vectors as rows of one 2-D dataset per leaf name
// (docs/storage.md). Writers write 2; readers read both.
inline constexpr int kSegmentFormatVersion = 2;

// Canonical file name of a segment: "seg-000042.h5" (at least six digits).
// Precondition: id.valid().
std::string segment_file_name(SegmentId id);

// The id of a canonical segment file name, or nullopt for any other name ("seg-42.h5",
// "seg-000042.h5.tmp", "notes.txt"): such files are never touched by the garbage collector.
std::optional<SegmentId> parse_segment_file_name(std::string_view file_name);

// Provenance stored as root attributes of every segment.
struct SegmentProvenance {
  std::string scene_hash;      // content hash of the scene (hex), "" if not known
  std::string writer_version;  // hapstate version that wrote it; filled in by the writer if ""
  std::string stage;           // stage that wrote it ("expand", "compact", ...), may be ""
};

// Whether `name` may name a vector in a segment: 1..255 characters, '/'-separated parts
// made of [A-Za-z0-9_.-], no empty part, no "." or ".." part (e.g. "c42/u"). A part before
// a '/' is an HDF5 group.
bool is_valid_vector_name(std::string_view name);

// Storage type of a vector in a segment. float64 for solver state (u, t, h); float32 for
// data only drawn on screen (displacement slopes); int32 for indices (touched nodes, tets).
enum class Precision { kFloat64, kFloat32, kInt32 };

}  // namespace hapstate
