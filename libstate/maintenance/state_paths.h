// Locating a state directory and measuring its files (docs/storage.md, docs/inspect.md):
// <dir>/catalogue.sqlite (+ -wal, -shm), <dir>/blobs/seg-NNNNNN.h5 (configuration vectors),
// <dir>/problem/ (the imported mesh and constraints). The layout is statedir/state_dir.h.
#pragma once

#include "statedir/state_dir.h"

#include <cstdint>
#include <filesystem>

namespace hapstate {

// The state directory `root`. Throws InputError naming `root` if it is not a directory
// ("no such state directory") or holds no catalogue.sqlite ("not a state directory").
StateDir locate_state(const std::filesystem::path& root);

// Bytes on disk of a state directory.
struct DiskUse {
  std::int64_t catalogue_bytes = 0;  // catalogue.sqlite + -wal + -shm
  std::int64_t blob_bytes = 0;       // every canonical segment file in blobs/
  std::int64_t segments = 0;         // number of canonical segment files in blobs/
  std::int64_t problem_bytes = 0;    // every file in problem/ (the imported mesh)
  std::int64_t total() const { return catalogue_bytes + blob_bytes + problem_bytes; }
};

// Measures the files now present (missing files count 0).
DiskUse measure_disk_use(const StateDir& dir);

}  // namespace hapstate
