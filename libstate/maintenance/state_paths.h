// The files of a state directory as the maintenance tools see them (docs/storage.md):
// <dir>/catalogue.sqlite (+ -wal, -shm), <dir>/blobs/seg-NNNNNN.h5 (configuration vectors) and
// <dir>/problem/ (the imported mesh and constraints, written once by hapstate-import).
#pragma once

#include <cstdint>
#include <filesystem>

namespace hapstate {

inline constexpr const char* kCatalogueFileName = "catalogue.sqlite";
inline constexpr const char* kBlobsDirName = "blobs";
inline constexpr const char* kProblemDirName = "problem";

struct StatePaths {
  std::filesystem::path root;
  std::filesystem::path catalogue;  // root / catalogue.sqlite
  std::filesystem::path blobs;      // root / blobs
  std::filesystem::path problem;    // root / problem
};

// The paths of the state directory `root`. Throws InputError naming `root` if it is not a
// directory or holds no catalogue.sqlite ("not a state directory").
StatePaths locate_state(const std::filesystem::path& root);

// Bytes on disk of a state directory.
struct DiskUse {
  std::int64_t catalogue_bytes = 0;  // catalogue.sqlite + -wal + -shm
  std::int64_t blob_bytes = 0;       // every canonical segment file in blobs/
  std::int64_t segments = 0;         // number of canonical segment files in blobs/
  std::int64_t problem_bytes = 0;    // every file in problem/ (the imported mesh)
  std::int64_t total() const { return catalogue_bytes + blob_bytes + problem_bytes; }
};

// Measures the files now present (missing files count 0).
DiskUse measure_disk_use(const StatePaths& dir);

}  // namespace hapstate
