// Content hashes of stage inputs (scene text, mesh file, scene fields a stage depends on), so
// a stage whose inputs did not change can skip. The algorithm is XXH64 (seed 0): fast, stable
// across platforms and releases, and its values match any other XXH64 implementation (e.g.
// `xxhsum -H64`). Not cryptographic: it detects changes, it does not resist a forger. With 64
// bits, an accidental collision between two different inputs has probability 2^-64 per pair.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace hapstate {

// A 64-bit content hash; written as 16 lowercase hex digits in the catalogue.
struct ContentHash {
  std::uint64_t value = 0;

  std::string hex() const;
  // Parses exactly 16 hex digits (either case); throws InputError otherwise.
  static ContentHash from_hex(std::string_view hex);
  friend constexpr auto operator<=>(ContentHash, ContentHash) = default;
};

// Incremental hashing: update() any number of times, then value(). Feeding the same bytes in
// any split gives the same value. Numbers are hashed in little-endian byte order, so a
// hash of doubles is the same on every platform. Not thread-safe (one hasher per thread).
class ContentHasher {
 public:
  ContentHasher& update(std::span<const std::byte> bytes);
  ContentHasher& update(std::string_view text);
  ContentHasher& update(std::span<const double> values);  // little-endian IEEE-754
  ContentHasher& update(double value);
  ContentHasher& update(std::int64_t value);  // little-endian two's complement
  // Hash of everything fed so far (the hasher stays usable).
  ContentHash value() const;

 private:
  std::uint64_t acc_[4] = {0x60ea27eeadc0b5d6ULL, 0xc2b2ae3d27d4eb4fULL, 0ULL,
                           0x61c8864e7a143579ULL};  // XXH64 lanes for seed 0
  unsigned char buffer_[32] = {};
  std::size_t buffered_ = 0;
  std::uint64_t total_ = 0;
};

ContentHash content_hash(std::string_view text);
ContentHash content_hash(std::span<const std::byte> bytes);

// Hash of a file's bytes (streamed, any size). Throws InputError naming the file if it cannot
// be read.
ContentHash content_hash_file(const std::filesystem::path& file);

}  // namespace hapstate
