// Byte sources for binary VTK XML data arrays: raw appended bytes or base64 text (decoded one
// 4-character group at a time, so separately encoded header and data blocks both decode), and
// the VTK block layout (a byte-count header, or a zlib block table when compressed).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace hapstate {

// Sequential reader of bytes; `read` returns false if fewer than n bytes remain.
class ByteStream {
 public:
  // `base64` selects decoding; `data` is the raw bytes or the base64 text.
  ByteStream(std::string_view data, bool base64) : data_(data), base64_(base64) {}
  // Appends the next n bytes to *out. Throws InputError-free: returns false on truncation;
  // sets *bad_char if the base64 text holds an invalid character.
  bool read(std::size_t n, std::string* out, bool* bad_char);

 private:
  std::string_view data_;
  bool base64_;
  std::size_t pos_ = 0;
  std::string pending_;  // decoded but not yet consumed
};

// Reads one VTK binary data block from `stream`: header integers of `header_size` bytes (4 or 8)
// in the given byte order, then the data, zlib-inflated if `zlib`. Returns the payload bytes.
// On failure returns false with a reason in *error.
bool read_vtk_block(ByteStream& stream, int header_size, bool swap, bool zlib, std::string* payload,
                    std::string* error);

}  // namespace hapstate
