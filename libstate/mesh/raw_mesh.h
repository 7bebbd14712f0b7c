// What a format reader produces before validation: node positions in file order, linear tets
// as 0-based node ids, and named groups of node ids. Readers resolve the file's own node tags
// (1-based, sparse, out of order) into these ids and throw file:line errors for bad references.
#pragma once

#include <algorithm>
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

// Maps a file's node tags to 0-based ids in file order. Dense storage for tags up to a few
// times the number of nodes registered so far (compact ranges, the usual case), a hash map for
// the others: memory stays proportional to the nodes the file really holds, whatever tags it
// names (a 40-byte file with the tag 6e7 once made a 268 MB table; found by fuzz_mesh_tetgen).
class NodeTags {
 public:
  // Registers the node `id` (the ids run 0, 1, 2, ...); false if `tag` was already used.
  bool add(long long tag, int id) {
    const long long bound = std::min<long long>(kDenseLimit, kDenseSlack * (id + 1LL) + kDenseMin);
    if (tag >= 0 && tag < bound) {
      const auto t = static_cast<std::size_t>(tag);
      if (t >= dense_.size()) dense_.resize(t + 1, -1);
      if (dense_[t] >= 0 || (!sparse_.empty() && sparse_.contains(tag))) return false;
      dense_[t] = id;
      return true;
    }
    if (tag >= 0 && static_cast<std::size_t>(tag) < dense_.size() &&
        dense_[static_cast<std::size_t>(tag)] >= 0)
      return false;
    return sparse_.emplace(tag, id).second;
  }
  // 0-based id of `tag`, or -1 if the file defines no such node.
  int find(long long tag) const {
    if (tag >= 0 && static_cast<std::size_t>(tag) < dense_.size() &&
        dense_[static_cast<std::size_t>(tag)] >= 0)
      return dense_[static_cast<std::size_t>(tag)];
    if (sparse_.empty()) return -1;
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }
  // Entries of the dense table (its memory in ints).
  std::size_t dense_size() const { return dense_.size(); }

 private:
  static constexpr long long kDenseLimit = 1LL << 26;  // tags above: always the hash map
  static constexpr long long kDenseSlack = 8;          // dense up to 8 x the nodes so far ...
  static constexpr long long kDenseMin = 1024;         // ... + 1024
  std::vector<int> dense_;
  std::unordered_map<long long, int> sparse_;
};

}  // namespace hapstate
