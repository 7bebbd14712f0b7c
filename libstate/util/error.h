// Error types shared by every layer. Bad input or state throws InputError with the file, the
// place and what is wrong already in the message; an I/O or environment failure throws
// EnvironmentError naming the file and the OS or library error. Mains map them to exit codes 2
// and 4 (util/main_guard.h).
#pragma once

#include <stdexcept>
#include <string>

namespace hapstate {

// Bad user input: a malformed file, a nonsense scene value, a corrupt database.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Not the user's input: the disk is full, a permission is missing, an I/O error, a database
// another process holds locked. Running again once the environment is fixed can succeed.
class EnvironmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Exit codes used by every executable (documented in docs/exit-codes.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     // internal error or a run that could not finish
inline constexpr int kExitBadInput = 2;    // usage, scene, mesh or state-directory error
inline constexpr int kExitSolveFailed = 3; // a solve did not converge (reason printed)
inline constexpr int kExitEnvironment = 4; // I/O or environment failure (disk full, permissions)

}  // namespace hapstate
