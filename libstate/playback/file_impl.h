// The mapped playback file as the runtime reads it: typed pointers into the mapping.
#pragma once

#include "hapstate/playback.h"
#include "playback/format.h"
#include "util/grid_direction.h"

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
  // kRefinedCellInts per configuration: refined cell (-1: none) and constraint bits, its
  // eighth-spacing lattice (-1: none) and constraint bits, its sixteenth-spacing lattice (-1:
  // none) and constraint bits; nullptr: none refined.
  const std::int32_t* refined_cells = nullptr;
  // 12 x kRefinedPoints per refined cell (section 21), with refined_cells.
  const double* refined_points = nullptr;
  std::int32_t num_refined_cells = 0;
  // 12 x kEighthPoints per eighth-spacing lattice (section 23); nullptr: none.
  const double* eighth_points = nullptr;
  std::int32_t num_eighth_cells = 0;
  // 12 x kSixteenthPoints per sixteenth-spacing lattice (section 27); nullptr: none.
  const double* sixteenth_points = nullptr;
  std::int32_t num_sixteenth_cells = 0;
  const playback::CertificateRecord* certificate = nullptr;  // section 22, nullptr: none
  // Sections 24-26 (contact, frictionless; their sizes checked at open, their contents by
  // verify(): the cursor checks what it reads); nullptr: none.
  const double* onset_triangles = nullptr;
  std::int32_t num_onset_triangles = 0;
  const std::int32_t* onset_cells = nullptr;  // grid points + 1
  const std::int32_t* onset_triangle_list = nullptr;
  std::int32_t onset_list_size = 0;
  // The displacements (kind 0) or their slope along axis kind - 1 at configuration c's
  // midpoint in direction d: 3 per view node.
  const float* midpoint_array(std::int32_t c, int d, int kind) const {
    const std::size_t n = 3 * static_cast<std::size_t>(meta->num_view_nodes);
    return midpoint_displacements +
           n * (4 * (playback::kMidpointDirections * static_cast<std::size_t>(c) + d) + kind);
  }

  // The grid-point numbering and the last cell (format.h) of this file's grid.
  std::int32_t point_index(const std::array<std::int32_t, 3>& ijk) const {
    return playback::grid_point_index(*meta, ijk);
  }
  std::array<std::int32_t, 3> point_ijk(std::int64_t g) const {
    return playback::grid_point_ijk(*meta, g);
  }
  std::int32_t last_cell(int a) const { return playback::last_cell(*meta, a); }
  // The target of configuration c's transition in direction d, or -1 if there is none
  // (undecided, outside, failed, or an index out of range in a damaged file).
  std::int32_t transition(std::int32_t c, int d) const {
    const std::int32_t t = transitions[grid::kDirections * static_cast<std::int64_t>(c) + d];
    return t >= 0 && t < meta->num_configurations ? t : -1;
  }
};

}  // namespace hapstate
