#include "catalogue/records.h"

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

}  // namespace hapstate
