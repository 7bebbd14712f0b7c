// Node-id list files used by [[fixed]] nodes = "..." and [probe] nodes = "...".
#pragma once

#include "scene/diagnostics.h"

#include <filesystem>
#include <vector>

namespace hapstate {

// Reads whitespace-separated 0-based node ids from `file` ('#' starts a comment that runs to
// the end of the line). Each id must be an integer in [0, num_nodes). Every bad token is
// recorded in `diagnostics` as "file:LINE: ..."; an unreadable file as one problem.
// Returns the valid ids, sorted and without repeats.
std::vector<int> read_node_ids(const std::filesystem::path& file, int num_nodes,
                               Diagnostics& diagnostics);

}  // namespace hapstate
