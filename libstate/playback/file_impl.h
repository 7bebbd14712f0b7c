// The mapped playback file as the runtime reads it: typed pointers into the mapping.
#pragma once

#include "hapstate/playback.h"
#include "playback/format.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace hapstate {

struct PlaybackFile::Impl {
  const std::byte* base = nullptr;
  std::size_t size = 0;
  const playback::FileHeader* header = nullptr;
  const playback::SectionEntry* table = nullptr;
  const playback::Meta* meta = nullptr;
  const std::int32_t* checkpoints = nullptr;  // [first, count] per grid point
  const std::int32_t* config_checkpoint = nullptr;
  const std::int32_t* config_level = nullptr;
  const std::int32_t* config_zero = nullptr;  // 1: a zero configuration
  const double* force = nullptr;
  const double* stiffness = nullptr;
  const std::int32_t* transitions = nullptr;
  const std::int32_t* view_nodes = nullptr;
  const float* reference = nullptr;
  const std::int32_t* triangles = nullptr;
  const float* displacements = nullptr;
  const float* slopes = nullptr;                 // nullptr: the file has none
  const double* clearance = nullptr;             // 4 per grid point; nullptr: a grab file
  const playback::OnsetCorner* onset = nullptr;  // 1 per configuration; nullptr: a grab file
  // 3 x kMidpointDirections per configuration (NaN: none); nullptr: the file has none.
  const double* midpoint_force = nullptr;
  // 9 x kMidpointDirections per configuration (NaN: none); nullptr: the file has none.
  const double* midpoint_stiffness = nullptr;
  // Bit d per configuration: its midpoint in direction d has displacements; nullptr: none.
  const std::int32_t* midpoint_mask = nullptr;
  // 12 x kMidpointDirections per view node per configuration (section 19); with the mask.
  const float* midpoint_displacements = nullptr;
  // 2 per configuration: refined cell (-1: none) and constraint bits; nullptr: none refined.
  const std::int32_t* refined_cells = nullptr;
  // 12 x kRefinedPoints per refined cell (section 21), with refined_cells.
  const double* refined_points = nullptr;
  std::int32_t num_refined_cells = 0;
  const playback::CertificateRecord* certificate = nullptr;  // section 22, nullptr: none
  // The displacements (kind 0) or their slope along axis kind - 1 at configuration c's
  // midpoint in direction d: 3 per view node.
  const float* midpoint_array(std::int32_t c, int d, int kind) const {
    const std::size_t n = 3 * static_cast<std::size_t>(meta->num_view_nodes);
    return midpoint_displacements +
           n * (4 * (playback::kMidpointDirections * static_cast<std::size_t>(c) + d) + kind);
  }

  // Linear index of grid point ijk (absolute grid indices), or -1 outside the grid.
  std::int32_t point_index(const std::array<std::int32_t, 3>& ijk) const {
    std::int32_t g = 0;
    for (int a = 0; a < 3; ++a) {
      const std::int32_t i = ijk[a] - meta->lo[a];
      if (i < 0 || i >= meta->dims[a]) return -1;
      g = g * meta->dims[a] + i;
    }
    return g;
  }
  // Grid index ijk of linear grid point g, the inverse of point_index; a g out of range (a
  // damaged file) gives the first grid point, so that callers stay defined.
  std::array<std::int32_t, 3> point_ijk(std::int64_t g) const {
    const std::int64_t points = std::int64_t(meta->dims[0]) * meta->dims[1] * meta->dims[2];
    if (g < 0 || g >= points) g = 0;
    const std::int64_t yz = std::int64_t(meta->dims[1]) * meta->dims[2];
    return {meta->lo[0] + static_cast<std::int32_t>(g / yz),
            meta->lo[1] + static_cast<std::int32_t>((g / meta->dims[2]) % meta->dims[1]),
            meta->lo[2] + static_cast<std::int32_t>(g % meta->dims[2])};
  }
  // Grid index of the last cell's first corner along axis a: a cell spans [base, base + 1];
  // with a single check-point along an axis the cell is degenerate there (s = 0 always).
  std::int32_t last_cell(int a) const {
    return meta->lo[a] + (meta->dims[a] > 1 ? meta->dims[a] - 2 : 0);
  }
  // The target of configuration c's transition in direction d, or -1 if there is none
  // (undecided, outside, failed, or an index out of range in a damaged file).
  std::int32_t transition(std::int32_t c, int d) const {
    const std::int32_t t = transitions[26 * static_cast<std::int64_t>(c) + d];
    return t >= 0 && t < meta->num_configurations ? t : -1;
  }
};

}  // namespace hapstate
