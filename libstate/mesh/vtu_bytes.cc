#include "mesh/vtu_bytes.h"

#include "mesh/binary.h"

#include <zlib.h>

#include <cstdint>
#include <vector>

namespace hapstate {
namespace {

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

}  // namespace

bool ByteStream::read(std::size_t n, std::string* out, bool* bad_char) {
  if (!base64_) {
    if (n > data_.size() - pos_) return false;
    out->append(data_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  while (pending_.size() < n) {
    char quad[4];
    int got = 0;
    while (got < 4 && pos_ < data_.size()) {
      const char c = data_[pos_++];
      if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
      quad[got++] = c;
    }
    if (got < 4) return false;
    int values[4];
    int pad = 0;
    for (int i = 0; i < 4; ++i) {
      if (quad[i] == '=' && i >= 2) {
        values[i] = 0;
        ++pad;
      } else {
        values[i] = base64_value(quad[i]);
        if (values[i] < 0 || pad > 0) {
          *bad_char = true;
          return false;
        }
      }
    }
    const std::uint32_t bits = (static_cast<std::uint32_t>(values[0]) << 18) |
                               (static_cast<std::uint32_t>(values[1]) << 12) |
                               (static_cast<std::uint32_t>(values[2]) << 6) |
                               static_cast<std::uint32_t>(values[3]);
    const char bytes[3] = {static_cast<char>(bits >> 16), static_cast<char>((bits >> 8) & 0xff),
                           static_cast<char>(bits & 0xff)};
    pending_.append(bytes, static_cast<std::size_t>(3 - pad));
  }
  out->append(pending_, 0, n);
  pending_.erase(0, n);
  return true;
}

bool read_vtk_block(ByteStream& stream, int header_size, bool swap, bool zlib, std::string* payload,
                    std::string* error) {
  bool bad_char = false;
  std::string header;
  const auto header_value = [&](std::size_t index) -> std::uint64_t {
    const char* p = header.data() + index * static_cast<std::size_t>(header_size);
    return header_size == 4 ? load_binary<std::uint32_t>(p, swap)
                            : load_binary<std::uint64_t>(p, swap);
  };
  const auto fail = [&](const std::string& what) {
    *error = bad_char ? "invalid base64 character in binary data" : what;
    return false;
  };
  if (!zlib) {
    if (!stream.read(static_cast<std::size_t>(header_size), &header, &bad_char))
      return fail("truncated binary data (no block header)");
    const std::uint64_t bytes = header_value(0);
    if (bytes > (std::uint64_t{1} << 40))
      return fail("corrupt block header (" + std::to_string(bytes) + " bytes)");
    if (!stream.read(static_cast<std::size_t>(bytes), payload, &bad_char)) {
      return fail("truncated binary data: header announces " + std::to_string(bytes) + " bytes");
    }
    return true;
  }
  if (!stream.read(3 * static_cast<std::size_t>(header_size), &header, &bad_char))
    return fail("truncated compressed block header");
  const std::uint64_t blocks = header_value(0);
  const std::uint64_t block_size = header_value(1);
  const std::uint64_t last_size = header_value(2);
  if (blocks > (1u << 24) || block_size > (std::uint64_t{1} << 32))
    return fail("corrupt compressed block header");
  if (!stream.read(static_cast<std::size_t>(blocks * static_cast<std::uint64_t>(header_size)),
                   &header, &bad_char)) {
    return fail("truncated compressed block table");
  }
  std::string compressed;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t csize = header_value(static_cast<std::size_t>(3 + b));
    compressed.clear();
    if (csize > (std::uint64_t{1} << 34) ||
        !stream.read(static_cast<std::size_t>(csize), &compressed, &bad_char)) {
      return fail("truncated compressed block " + std::to_string(b));
    }
    const std::uint64_t usize = (b + 1 == blocks && last_size != 0) ? last_size : block_size;
    // zlib inflates at most about 1032:1: a larger announced size is a corrupt header, not a
    // reason to allocate it.
    if (usize > 1040 * csize + 64) {
      return fail("compressed block " + std::to_string(b) + " announces " + std::to_string(usize) +
                  " bytes from " + std::to_string(csize) +
                  " compressed (more than zlib can inflate)");
    }
    const std::size_t old = payload->size();
    payload->resize(old + static_cast<std::size_t>(usize));
    uLongf out_size = static_cast<uLongf>(usize);
    const int rc =
        uncompress(reinterpret_cast<Bytef*>(payload->data() + old), &out_size,
                   reinterpret_cast<const Bytef*>(compressed.data()), static_cast<uLong>(csize));
    if (rc != Z_OK || out_size != usize)
      return fail("zlib could not inflate block " + std::to_string(b) + " (corrupt data)");
  }
  return true;
}

}  // namespace hapstate
