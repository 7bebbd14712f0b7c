// PRIVATE to the blobs module: the layout of a format-2 segment (docs/storage.md), shared by
// the writer and the reader.
//
//   /<leaf>                        2-D dataset [rows x width]: row r holds the vector
//                                  "<group>/<leaf>" of the r-th group written with this leaf
//                                  (shorter rows padded with zeros)
//   /hapstate_index/groups         uint8: the group names, each followed by '\n' ("" for a
//                                  vector without a group)
//   /hapstate_index/<leaf>         int64 [rows x 2]: per row the group's index and the length
#pragma once

#include <string>
#include <string_view>

namespace hapstate::blobs_detail {

inline constexpr const char* kIndexGroup = "hapstate_index";
inline constexpr const char* kGroupsDataset = "hapstate_index/groups";

// "<group>/<leaf>" split at the last '/' (group "" when there is none).
inline std::pair<std::string, std::string> split_vector_name(std::string_view name) {
  const std::size_t slash = name.rfind('/');
  if (slash == std::string_view::npos) return {"", std::string(name)};
  return {std::string(name.substr(0, slash)), std::string(name.substr(slash + 1))};
}

}  // namespace hapstate::blobs_detail
