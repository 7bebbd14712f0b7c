// Shared by the libFuzzer harnesses (fuzz/README.md): what counts as a finding. A harness
// feeds bytes to one reader; the reader may accept them or reject them with the documented
// errors (InputError: bad input, and for files EnvironmentError); any other exception, a crash,
// a sanitizer report or a hang is a finding.
#pragma once

#include "util/error.h"

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace hapstate::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A per-process scratch file for readers that take a path (on tmpfs when there is one).
inline std::filesystem::path scratch(const std::string& name) {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d =
        std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    d /= "hapstate_fuzz_" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / name;
}

inline std::filesystem::path write_scratch(const std::string& name, const std::uint8_t* data,
                                           std::size_t size) {
  const std::filesystem::path file = scratch(name);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace hapstate::fuzz
