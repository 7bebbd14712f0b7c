#include "statedir/state_dir.h"

#include "util/error.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <initializer_list>

namespace hapstate {

StateDirLock::StateDirLock(const StateDir& dir) {
  const std::filesystem::path file = dir.root / kFileName;
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    // A missing state directory is the user's; a full disk, a permission, a read-only file
    // system the environment's.
    const int error = errno;
    const std::string message =
        file.string() + ": cannot create the state lock: " + os_error_text(error);
    if (error == ENOENT || error == ENOTDIR) throw InputError(message);
    throw EnvironmentError(message);
  }
  // A few quick retries: hapstate-inspect probes the lock with a shared lock for an instant.
  bool locked = false;
  for (int attempt = 0; attempt < 20 && !locked; ++attempt) {
    locked = ::flock(fd_, LOCK_EX | LOCK_NB) == 0;
    if (!locked && errno != EWOULDBLOCK) break;
    if (!locked) ::usleep(5000);
  }
  if (!locked) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      throw InputError(dir.root.string() +
                       ": another hapstate stage is working in this state "
                       "directory; wait until it has finished");
    }
    throw EnvironmentError(dir.root.string() +
                           ": cannot lock the state directory: " + os_error_text(error));
  }
}

StateDirLock::~StateDirLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

bool state_dir_busy(const StateDir& dir) {
  const int fd = ::open((dir.root / StateDirLock::kFileName).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;  // no stage ever locked it
  const bool busy = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // releases the shared lock if we got it
  return busy;
}

bool is_hapstate_catalogue_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<unsigned char, 100> header{};
  if (!in.read(reinterpret_cast<char*>(header.data()), header.size())) return false;
  if (std::memcmp(header.data(), "SQLite format 3", 16) != 0) return false;
  const std::uint32_t id = (std::uint32_t{header[68]} << 24) | (std::uint32_t{header[69]} << 16) |
                           (std::uint32_t{header[70]} << 8) | std::uint32_t{header[71]};
  return id == static_cast<std::uint32_t>(Catalogue::kApplicationId);
}

Catalogue open_imported_catalogue(const StateDir& dir, OpenMode mode) {
  if (!std::filesystem::is_directory(dir.root)) {
    throw InputError(dir.root.string() + ": no such state directory (run hapstate-import first)");
  }
  if (!std::filesystem::exists(dir.catalogue())) {
    throw InputError(dir.root.string() +
                     ": not a state directory: no catalogue.sqlite (run hapstate-import first)");
  }
  Catalogue catalogue(dir.catalogue(), mode);
  if (!catalogue.read_scene()) {
    throw InputError(dir.catalogue().string() +
                     ": no scene has been imported (run hapstate-import first)");
  }
  return catalogue;
}

void remove_state_files(const StateDir& dir) {
  namespace fs = std::filesystem;
  for (const char* name : {"catalogue.sqlite", "catalogue.sqlite-wal", "catalogue.sqlite-shm",
                           "catalogue.sqlite-journal", "playback.bin"}) {
    fs::remove(dir.root / name);
  }
  fs::remove_all(dir.blobs());
  fs::remove_all(dir.problem());
}

StageRun require_stage_run(Catalogue& catalogue, const StateDir& dir, const std::string& stage) {
  auto run = catalogue.last_successful_stage_run(stage);
  if (!run) {
    throw InputError(dir.root.string() + ": hapstate-" + stage +
                     " has not run in this state directory yet: run it first");
  }
  return *run;
}

std::optional<ContentHash> run_input(const StageRun& run, const std::string& name) {
  for (const auto& [n, h] : run.inputs)
    if (n == name) return h;
  return std::nullopt;
}

}  // namespace hapstate
