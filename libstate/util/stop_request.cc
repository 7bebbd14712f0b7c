#include "util/stop_request.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

namespace hapstate {
namespace {

std::atomic<int> g_stop{0};  // lock-free: safe from a handler and across threads
static_assert(std::atomic<int>::is_always_lock_free);
const char* g_message = "";
std::size_t g_message_size = 0;

constexpr char kAtOnce[] =
    "\nstopped at once; the work committed so far is kept: run the same command again to "
    "resume\n";

// Only async-signal-safe calls: write(2) and _exit(2).
extern "C" void on_stop_signal(int) {
  const int saved_errno = errno;
  if (g_stop.load()) {  // the second signal: end now (as a kill would; resuming is safe)
    ssize_t ignored = ::write(STDERR_FILENO, kAtOnce, sizeof kAtOnce - 1);
    (void)ignored;
    ::_exit(130);
  }
  g_stop.store(1);
  ssize_t ignored = ::write(STDERR_FILENO, g_message, g_message_size);
  (void)ignored;
  errno = saved_errno;
}

}  // namespace

void install_stop_request_handler(const char* message) {
  g_message = message;
  g_message_size = std::strlen(message);
  g_stop.store(0);
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() { return g_stop.load() != 0; }

}  // namespace hapstate
