// Writing a playback file (hapstate-index): everything but the displacements is held in
// memory; the displacements are streamed one configuration at a time.
#pragma once

#include "playback/format.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

namespace hapstate::playback {

struct Content {
  Meta meta{};  // counts are filled in from the vectors below; force_change_bound computed
  std::vector<std::int32_t> checkpoints;        // 2 per grid point
  std::vector<std::int32_t> config_checkpoint;  // per configuration
  std::vector<std::int32_t> config_level;
  std::vector<std::int32_t> config_zero;  // 1: a zero configuration (body at rest)
  std::vector<double> force;              // 3 per configuration
  std::vector<double> stiffness;          // 9 per configuration
  std::vector<std::int32_t> transitions;  // 26 per configuration
  std::vector<std::int32_t> view_nodes;
  std::vector<float> reference;         // 3 per view node
  std::vector<std::int32_t> triangles;  // 3 per triangle, view-node indices
  std::vector<double> clearance;        // contact: 4 per grid point (gap, gradient); grab: empty
  std::vector<OnsetCorner> onset;       // contact: 1 per configuration (onset_model.h); grab: empty
  // Contact, frictionless (onset_model.h, add_onset_triangles): 9 per rest triangle near the
  // onset; per grid point + 1 the start of its cell's list; the lists. Empty: none.
  std::vector<double> onset_triangles;
  std::vector<std::int32_t> onset_cells;
  std::vector<std::int32_t> onset_triangle_list;
  // 3 x kMidpointDirections per configuration (NaN: none), or empty: none recorded.
  std::vector<double> midpoint_force;
  // 9 x kMidpointDirections per configuration (NaN: none), or empty: none recorded (then also
  // when midpoint_force is empty).
  std::vector<double> midpoint_stiffness;
  // Per configuration, bit d: the displacements at the midpoint in direction d are given by
  // midpoint_displacements; empty: none (the file then has none).
  std::vector<std::int32_t> midpoint_displacement_mask;
  // Fills `out` (12 x kMidpointDirections per view node, the layout of section 19) for
  // configuration c; called only when the mask is not empty.
  std::function<void(std::int32_t c, std::span<float> out)> midpoint_displacements;
  // Per configuration (kRefinedCellInts): the refined cell whose lowest corner it is (index into
  // refined_points, or -1) and its constraint bits (format.h), its eighth-spacing lattice (index
  // into eighth_points, or -1) and that lattice's constraint bits, its sixteenth-spacing lattice
  // (index into sixteenth_points, or -1) and its constraint bits; empty: no refined cell.
  std::vector<std::int32_t> refined_cells;
  // 12 x kRefinedPoints per refined cell: force and stiffness per lattice point (NaN: none).
  std::vector<double> refined_points;
  // 12 x kEighthPoints per eighth-spacing lattice, as refined_points.
  std::vector<double> eighth_points;
  // 12 x kSixteenthPoints per sixteenth-spacing lattice, as refined_points.
  std::vector<double> sixteenth_points;
  // Fills `out` (3 per view node) with the displacements of configuration c.
  std::function<void(std::int32_t c, std::span<float> out)> displacements;
  // Fills `out` (9 per view node: the x, y, z arrays of 3 per view node) with the
  // displacement slopes of configuration c; empty: the file has none (Meta flag 0).
  std::function<void(std::int32_t c, std::span<float> out)> displacement_slopes;
};

// The bound on |f(p) - f(q)| / |p - q| the cursor keeps (docs/playback.md), from the forces of
// configurations at neighbouring grid points and the stiffness of every configuration.
double force_change_bound(const Content& content);

// Writes `content` to `file` atomically: a temporary file in the same directory, fsynced,
// then renamed over `file` (an existing file stays intact until then). Throws InputError
// naming the file on an I/O error or inconsistent content.
void write_file(Content content, const std::filesystem::path& file);

// Puts `record` into the certificate section of the playback file `file` (replacing one it
// holds), atomically as write_file: a copy with the section filled and the same permissions is
// renamed over `file`, so a program that has the old file mapped keeps reading it. Throws
// InputError if `file` is not a playback file of this version or fails verify(),
// EnvironmentError on an I/O error.
void write_certificate(const std::filesystem::path& file, const CertificateRecord& record);

}  // namespace hapstate::playback
