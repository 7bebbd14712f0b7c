#include "catalogue/records.h"

#include <algorithm>

namespace hapstate {

const char* BlobRef::leaf(BlobVector v) {
  switch (v) {
    case BlobVector::kU:
      return "u";
    case BlobVector::kT:
      return "t";
    case BlobVector::kH:
      return "h";
    case BlobVector::kDuDp:
      return "du_dp";
    case BlobVector::kTouched:
      return "touched";
    case BlobVector::kMultipliers:
      return "multipliers";
  }
  return "u";
}

std::string BlobRef::configuration_group(std::int64_t config) {
  std::string name = "c";  // (not "c" + ...: GCC 12's false -Wrestrict, bug 105329)
  name += std::to_string(config);
  return name;
}

std::string BlobRef::midpoint_group(std::int64_t source, int direction) {
  std::string name = "m";
  name += std::to_string(source);
  name += '_';
  name += std::to_string(direction);
  return name;
}

namespace {

bool all_digits(std::string_view s) {
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
}

}  // namespace

bool BlobRef::is_state_group(std::string_view group) {
  if (group.size() < 2) return false;
  if (group[0] == 'c') return all_digits(group.substr(1));
  const std::size_t underscore = group.find('_');
  return group[0] == 'm' && underscore != std::string_view::npos &&
         all_digits(group.substr(1, underscore - 1)) && all_digits(group.substr(underscore + 1));
}

}  // namespace hapstate
