// Loading fixed-size numbers from raw bytes of either byte order (binary MSH, VTK, VTU).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace hapstate {

// True if the host is little-endian.
inline constexpr bool kHostLittleEndian = std::endian::native == std::endian::little;

// Reads a T stored at `p` (no alignment needed); `swap` reverses the byte order.
template <class T>
T load_binary(const char* p, bool swap) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      const char c = bytes[i];
      bytes[i] = bytes[sizeof(T) - 1 - i];
      bytes[sizeof(T) - 1 - i] = c;
    }
  }
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

}  // namespace hapstate
