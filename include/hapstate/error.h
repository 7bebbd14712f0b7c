// The exceptions hapstate throws (hapstate/solver.h, and every stage and tool inside). Bad input
// or state throws InputError with the file, the place and what is wrong already in the
// message; an I/O or environment failure throws EnvironmentError naming the file and the OS or
// library error. The executables map them to exit codes 2 and 4 (docs/exit-codes.md).
#pragma once

#include <stdexcept>

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

}  // namespace hapstate
