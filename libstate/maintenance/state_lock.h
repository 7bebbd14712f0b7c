// An advisory exclusive lock on a state directory: flock(2) on <state>/lock. Held by
// hapstate-compact for its whole run, so that two compactions never interleave, and meant to be
// taken by every writing stage (then compaction cannot delete a segment a running stage has
// written but not yet committed). The lock dies with its process (kill -9 releases it); the
// file itself stays and is harmless.
#pragma once

#include <filesystem>

namespace hapstate {

inline constexpr const char* kStateLockFileName = "lock";

class StateLock {
 public:
  // Takes the lock without waiting. Throws InputError naming the directory if another process
  // holds it ("another hapstate process is working on ..."), or if the file cannot be created.
  explicit StateLock(const std::filesystem::path& state_root);
  ~StateLock();
  StateLock(const StateLock&) = delete;
  StateLock& operator=(const StateLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace hapstate
