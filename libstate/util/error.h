// Error types shared by every layer (hapstate/error.h: InputError for bad input or state,
// EnvironmentError for I/O and environment failures) and the exit codes every executable maps
// them to (util/main_guard.h, docs/exit-codes.md).
#pragma once

#include "hapstate/error.h"

#include <cstring>
#include <string>

namespace hapstate {

// Exit codes used by every executable (documented in docs/exit-codes.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;      // internal error or a run that could not finish
inline constexpr int kExitBadInput = 2;     // usage, scene, mesh or state-directory error
inline constexpr int kExitSolveFailed = 3;  // a solve did not converge (reason printed)
inline constexpr int kExitEnvironment = 4;  // I/O or environment failure (disk full, permissions)

// The operating system's text for the errno value `errnum` ("No space left on device"). Unlike
// std::strerror it is safe to call from several threads at once.
inline std::string os_error_text(int errnum) {
  char buffer[256];
  return ::strerror_r(errnum, buffer, sizeof buffer);  // the GNU form returns the text
}

}  // namespace hapstate
