#include "blobs/segment.h"

#include <algorithm>
#include <cassert>
#include <cstdio>

namespace hapstate {

std::string segment_file_name(SegmentId id) {
  assert(id.valid());
  char name[40];
  std::snprintf(name, sizeof name, "seg-%06lld.h5", static_cast<long long>(id.value));
  return name;
}

std::optional<SegmentId> parse_segment_file_name(std::string_view file_name) {
  constexpr std::string_view kPrefix = "seg-";
  constexpr std::string_view kSuffix = ".h5";
  if (file_name.size() <= kPrefix.size() + kSuffix.size() || !file_name.starts_with(kPrefix) ||
      !file_name.ends_with(kSuffix)) {
    return std::nullopt;
  }
  const std::string_view digits =
      file_name.substr(kPrefix.size(), file_name.size() - kPrefix.size() - kSuffix.size());
  if (digits.size() > 18) return std::nullopt;
  std::int64_t value = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + (c - '0');
  }
  const SegmentId id{value};
  if (!id.valid() || segment_file_name(id) != file_name) return std::nullopt;  // not canonical
  return id;
}

bool is_valid_vector_name(std::string_view name) {
  if (name.empty() || name.size() > 255) return false;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t slash = std::min(name.find('/', start), name.size());
    const std::string_view part = name.substr(start, slash - start);
    if (part.empty() || part == "." || part == "..") return false;
    for (char c : part) {
      const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '_' || c == '.' || c == '-';
      if (!ok) return false;
    }
    start = slash + 1;
  }
  return true;
}

}  // namespace hapstate
