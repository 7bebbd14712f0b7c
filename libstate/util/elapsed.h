// Wall time since a steady-clock instant, in seconds (solver timings, rates).
#pragma once

#include <chrono>

namespace hapstate {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace hapstate
