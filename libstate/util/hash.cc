#include "util/hash.h"

#include "util/error.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <vector>

namespace hapstate {
namespace {

constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ULL;
constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4FULL;
constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ULL;
constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ULL;
constexpr std::uint64_t kPrime5 = 0x27D4EB2F165667C5ULL;

std::uint64_t load64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];  // little-endian on any host
  return v;
}

std::uint32_t load32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

std::uint64_t lane_round(std::uint64_t acc, std::uint64_t input) {
  acc += input * kPrime2;
  acc = std::rotl(acc, 31);
  return acc * kPrime1;
}

std::uint64_t merge_lane(std::uint64_t hash, std::uint64_t lane) {
  hash ^= lane_round(0, lane);
  return hash * kPrime1 + kPrime4;
}

void consume_stripe(std::uint64_t acc[4], const unsigned char* stripe) {
  for (int lane = 0; lane < 4; ++lane) acc[lane] = lane_round(acc[lane], load64(stripe + 8 * lane));
}

void put_le64(unsigned char out[8], std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(v >> (8 * i));
}

}  // namespace

std::string ContentHash::hex() const {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text(16, '0');
  for (int i = 0; i < 16; ++i) text[15 - i] = kDigits[(value >> (4 * i)) & 0xF];
  return text;
}

ContentHash ContentHash::from_hex(std::string_view hex) {
  if (hex.size() != 16) {
    throw InputError("content hash '" + std::string(hex) + "': expected 16 hex digits");
  }
  std::uint64_t v = 0;
  for (char c : hex) {
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    if (digit < 0) throw InputError("content hash '" + std::string(hex) + "': not a hex digit");
    v = (v << 4) | static_cast<std::uint64_t>(digit);
  }
  return ContentHash{v};
}

ContentHasher& ContentHasher::update(std::span<const std::byte> bytes) {
  if (bytes.empty()) return *this;  // an empty span's data() may be null (memcpy's UB)
  auto p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t n = bytes.size();
  total_ += n;
  if (buffered_ > 0) {
    const std::size_t take = std::min(n, sizeof buffer_ - buffered_);
    std::memcpy(buffer_ + buffered_, p, take);
    buffered_ += take;
    p += take;
    n -= take;
    if (buffered_ < sizeof buffer_) return *this;
    consume_stripe(acc_, buffer_);
    buffered_ = 0;
  }
  for (; n >= 32; p += 32, n -= 32) consume_stripe(acc_, p);
  std::memcpy(buffer_, p, n);
  buffered_ = n;
  return *this;
}

ContentHasher& ContentHasher::update(std::string_view text) {
  return update(std::as_bytes(std::span<const char>(text.data(), text.size())));
}

ContentHasher& ContentHasher::update(std::span<const double> values) {
  for (double v : values) update(v);
  return *this;
}

ContentHasher& ContentHasher::update(double value) {
  unsigned char bytes[8];
  put_le64(bytes, std::bit_cast<std::uint64_t>(value));
  return update(std::as_bytes(std::span<const unsigned char>(bytes, 8)));
}

ContentHasher& ContentHasher::update(std::int64_t value) {
  unsigned char bytes[8];
  put_le64(bytes, static_cast<std::uint64_t>(value));
  return update(std::as_bytes(std::span<const unsigned char>(bytes, 8)));
}

ContentHash ContentHasher::value() const {
  std::uint64_t h = 0;
  if (total_ >= 32) {
    h = std::rotl(acc_[0], 1) + std::rotl(acc_[1], 7) + std::rotl(acc_[2], 12) +
        std::rotl(acc_[3], 18);
    for (int lane = 0; lane < 4; ++lane) h = merge_lane(h, acc_[lane]);
  } else {
    h = kPrime5;  // seed 0
  }
  h += total_;
  const unsigned char* p = buffer_;
  std::size_t n = buffered_;
  for (; n >= 8; p += 8, n -= 8) {
    h ^= lane_round(0, load64(p));
    h = std::rotl(h, 27) * kPrime1 + kPrime4;
  }
  if (n >= 4) {
    h ^= static_cast<std::uint64_t>(load32(p)) * kPrime1;
    h = std::rotl(h, 23) * kPrime2 + kPrime3;
    p += 4;
    n -= 4;
  }
  for (; n > 0; ++p, --n) {
    h ^= *p * kPrime5;
    h = std::rotl(h, 11) * kPrime1;
  }
  h ^= h >> 33;
  h *= kPrime2;
  h ^= h >> 29;
  h *= kPrime3;
  h ^= h >> 32;
  return ContentHash{h};
}

ContentHash content_hash(std::string_view text) { return ContentHasher().update(text).value(); }

ContentHash content_hash(std::span<const std::byte> bytes) {
  return ContentHasher().update(bytes).value();
}

ContentHash content_hash_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open for hashing");
  ContentHasher hasher;
  std::vector<char> block(1 << 16);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto got = in.gcount();
    if (got > 0)
      hasher.update(
          std::as_bytes(std::span<const char>(block.data(), static_cast<std::size_t>(got))));
  }
  if (in.bad()) throw InputError(file.string() + ": read error while hashing");
  return hasher.value();
}

}  // namespace hapstate
