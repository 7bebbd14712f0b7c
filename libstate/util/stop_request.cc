#include "util/stop_request.h"

#include <unistd.h>

#include <csignal>
#include <cstring>

namespace hapstate {
namespace {

volatile std::sig_atomic_t g_stop = 0;
const char* g_message = "";
std::size_t g_message_size = 0;

extern "C" void on_stop_signal(int signal_number) {
  g_stop = 1;
  // Only async-signal-safe calls: write(2) and resetting the disposition.
  ssize_t ignored = ::write(STDERR_FILENO, g_message, g_message_size);
  (void)ignored;
  std::signal(signal_number, SIG_DFL);
}

}  // namespace

void install_stop_request_handler(const char* message) {
  g_message = message;
  g_message_size = std::strlen(message);
  g_stop = 0;
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() { return g_stop != 0; }

}  // namespace hapstate
