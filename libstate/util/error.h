// Error types shared by every layer. Bad input or state throws InputError with the file, the
// place and what is wrong already in the message; stage mains map it to exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace hapstate {

// Bad user input: a malformed file, a nonsense scene value, a corrupt database.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Exit codes used by every executable (documented in docs/exit-codes.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     // internal error or a run that could not finish
inline constexpr int kExitBadInput = 2;    // usage, scene, mesh or state-directory error
inline constexpr int kExitSolveFailed = 3; // a solve did not converge (reason printed)

}  // namespace hapstate
