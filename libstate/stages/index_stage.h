// The index stage (hapstate-index): turns a state directory into one playback file
// (docs/playback.md) for the runtime (include/hapstate/playback.h).
#pragma once

#include "statedir/stage_run.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace hapstate {

enum class ViewNodes { kSurface, kAll };

struct IndexOptions {
  std::filesystem::path state;
  std::filesystem::path output;      // "" = <state>/playback.bin
  ViewNodes view = ViewNodes::kAll;  // whose displacements are stored
  std::FILE* progress = stderr;      // progress line; nullptr: none

  // Throws InputError naming the first missing option (run_index calls it first).
  void check() const;
};

// outcome: kOk (written) or kUnchanged (the file is up to date).
struct IndexReport : StageReport {
  std::filesystem::path output;
  std::int64_t configurations = 0;
  std::int64_t view_nodes = 0;
  std::int64_t bytes = 0;
  bool slopes = false;  // the file holds displacement slopes (Hermite deformation)
};

// Writes the playback file atomically (an existing file stays intact until the new one is
// complete) and records an "index" stage run. Skips ("unchanged") when the file exists, opens,
// and was built from the same configurations, transitions, problem and options. Throws
// InputError (nothing written) if the directory is not expanded or is inconsistent.
IndexReport run_index(const IndexOptions& options);

}  // namespace hapstate
