#include "maintenance/state_lock.h"

#include "util/error.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hapstate {

StateLock::StateLock(const std::filesystem::path& state_root) {
  const std::filesystem::path file = state_root / kStateLockFileName;
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw InputError(file.string() + ": cannot create the state lock: " + std::strerror(errno));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) {
      throw InputError(state_root.string() +
                       ": another hapstate process is working on this state directory (" +
                       file.string() + " is locked); run again when it has finished");
    }
    throw InputError(file.string() + ": cannot lock: " + std::strerror(err));
  }
}

StateLock::~StateLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

}  // namespace hapstate
