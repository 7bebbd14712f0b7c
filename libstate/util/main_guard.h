// The boundary of every executable: runs its body and maps exceptions to exit codes
// (InputError -> kExitBadInput, EnvironmentError -> kExitEnvironment, with their messages;
// anything else -> kExitFailure).
#pragma once

#include "util/error.h"

#include <cstdio>
#include <exception>
#include <new>

namespace hapstate {

template <typename Body>
int guarded_main(const char* program, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return kExitBadInput;
  } catch (const EnvironmentError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return kExitEnvironment;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", program);
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", program, e.what());
    return kExitFailure;
  }
}

}  // namespace hapstate
