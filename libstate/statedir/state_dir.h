// The layout of a state directory (docs/storage.md, docs/state-space.md):
//   <root>/catalogue.sqlite   metadata and every decision
//   <root>/blobs/             HDF5 segments of configuration vectors
//   <root>/problem/           one HDF5 segment: the imported mesh and constraints
#pragma once

#include "catalogue/catalogue.h"
#include "catalogue/records.h"

#include <filesystem>
#include <optional>
#include <string>

namespace hapstate {

struct StateDir {
  std::filesystem::path root;

  std::filesystem::path catalogue() const { return root / "catalogue.sqlite"; }
  std::filesystem::path blobs() const { return root / "blobs"; }
  std::filesystem::path problem() const { return root / "problem"; }
};

// An exclusive lock on a state directory for one stage run: flock(2) on <root>/lock (the same
// file and protocol as hapstate-compact's lock, so all writing stages exclude each other; the
// lock dies with its process, even by kill -9; the file stays and is harmless). Stages that
// write a state directory hold it, so two of them never work in one directory at once (the
// expand stage's garbage collection would delete another run's uncommitted segment).
class StateDirLock {
 public:
  static constexpr const char* kFileName = "lock";

  // Locks dir.root (which must exist). Throws InputError "<dir>: another hapstate stage is
  // working in this state directory ..." if another process holds it.
  explicit StateDirLock(const StateDir& dir);
  ~StateDirLock();
  StateDirLock(const StateDirLock&) = delete;
  StateDirLock& operator=(const StateDirLock&) = delete;

 private:
  int fd_ = -1;
};

// Whether a live process holds `dir`'s lock now (a stage is working there). A stage run the
// catalogue records as running while nobody holds the lock was killed.
bool state_dir_busy(const StateDir& dir);

// Whether `file` starts like a hapstate catalogue: an SQLite header whose application_id is
// Catalogue::kApplicationId. Reads 100 bytes; false for a missing or short file.
bool is_hapstate_catalogue_file(const std::filesystem::path& file);

// Opens the catalogue of an imported state directory (the scene row must exist). Throws
// InputError naming the directory if it is not a state directory ("run hapstate-import
// first"), or whatever Catalogue's constructor refuses (future schema, corrupt, foreign).
Catalogue open_imported_catalogue(const StateDir& dir, OpenMode mode);

// Removes what a state directory holds (catalogue files, blobs/, problem/, playback.bin) and
// nothing else. Precondition: the catalogue, if present, is a hapstate catalogue.
void remove_state_files(const StateDir& dir);

// The newest successful run of `stage`, or an InputError "<dir>: hapstate-<stage> has not
// run here yet: run it first".
StageRun require_stage_run(Catalogue& catalogue, const StateDir& dir, const std::string& stage);

// The input `name` of `run`, if recorded.
std::optional<ContentHash> run_input(const StageRun& run, const std::string& name);

}  // namespace hapstate
