// The refined cells of a playback file (sections 20, 21, 23 and 27, docs/playback.md "Refined
// cells"): the refine stage's points per cell, and which faces and edges of each border a cell that
// is not refined.
#pragma once

#include "catalogue/records.h"
#include "playback/writer.h"

#include <cstdint>
#include <map>
#include <vector>

namespace hapstate {

// Fills content->refined_cells, refined_points and eighth_points from the complete refined cells
// among `rows` (every point of a lattice present; an eighth-spacing lattice only with its
// quarter-spacing one; cells whose lowest corner is not in the file are left out).
// index_of maps a configuration id to its index in the file; content's configurations, grid and
// midpoint stiffness must be filled in (a file without midpoint stiffness gets no refined cell).
void add_refined_cells(const std::vector<RefinementPoint>& rows,
                       const std::map<std::int64_t, std::int32_t>& index_of,
                       playback::Content* content);

}  // namespace hapstate
