#include "scene/node_list.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>
#include <string>

namespace hapstate {

std::vector<int> read_node_ids(const std::filesystem::path& file, int num_nodes,
                               Diagnostics& diagnostics) {
  const std::string name = file.string();
  std::ifstream in(file);
  if (!in) {
    diagnostics.add_in(name, 0, "cannot open node list");
    return {};
  }
  std::vector<int> ids;
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream tokens(line);
    std::string token;
    while (tokens >> token) {
      long long id = 0;
      const char* end = token.data() + token.size();
      const auto [ptr, ec] = std::from_chars(token.data(), end, id);
      if (ec != std::errc() || ptr != end) {
        diagnostics.add_in(name, line_number,
                           "'" + token + "' is not a node id (a 0-based integer)");
      } else if (id < 0 || id >= num_nodes) {
        diagnostics.add_in(name, line_number,
                           "node id " + token + " out of range: the mesh has " +
                               std::to_string(num_nodes) + " nodes (ids 0.." +
                               std::to_string(num_nodes - 1) + ")");
      } else {
        ids.push_back(static_cast<int>(id));
      }
    }
  }
  if (in.bad()) diagnostics.add_in(name, 0, "read error");
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace hapstate
