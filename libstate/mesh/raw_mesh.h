// What a format reader produces before validation: node positions in file order, linear tets
// as 0-based node ids, and named groups of node ids. Readers resolve the file's own node tags
// (1-based, sparse, out of order) into these ids and throw file:line errors for bad references.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace hapstate {

struct RawMesh {
  std::string source;                              // file name for messages
  std::vector<double> xyz;                         // 3 coordinates per node, file order
  std::vector<std::array<int, 4>> tets;            // 0-based node ids, file order
  std::map<std::string, std::vector<int>> groups;  // node ids, unsorted, may repeat
  std::vector<std::string> warnings;               // reader remarks (ignored sections, ...)

  int num_nodes() const { return static_cast<int>(xyz.size() / 3); }
  // Appends `count` node ids to group `name`.
  void add_to_group(const std::string& name, const int* ids, int count) {
    auto& g = groups[name];
    g.insert(g.end(), ids, ids + count);
  }
};

// Maps a file's node tags to 0-based ids in file order. Dense storage for compact tag ranges,
// a hash map otherwise.
class NodeTags {
 public:
  // Registers the next node; false if `tag` was already used.
  bool add(long long tag, int id) {
    if (tag >= 0 && tag < kDenseLimit) {
      if (static_cast<std::size_t>(tag) >= dense_.size())
        dense_.resize(static_cast<std::size_t>(tag) + 1, -1);
      if (dense_[static_cast<std::size_t>(tag)] >= 0) return false;
      dense_[static_cast<std::size_t>(tag)] = id;
      return true;
    }
    return sparse_.emplace(tag, id).second;
  }
  // 0-based id of `tag`, or -1 if the file defines no such node.
  int find(long long tag) const {
    if (tag >= 0 && tag < kDenseLimit) {
      return static_cast<std::size_t>(tag) < dense_.size() ? dense_[static_cast<std::size_t>(tag)]
                                                           : -1;
    }
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }

 private:
  static constexpr long long kDenseLimit = 1LL << 26;
  std::vector<int> dense_;
  std::unordered_map<long long, int> sparse_;
};

}  // namespace hapstate
