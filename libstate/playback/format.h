// The playback file's layout on disk (docs/playback.md): little-endian, a 64-byte header,
// a table of sections, every section's data 64-byte aligned. Version 13 (kVersion).
//
//   header | section table | section data ...
//
// The header and the section table carry XXH64 checksums checked at open (O(1): a few
// hundred bytes); each section's checksum is checked by verify().
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace hapstate::playback {

static_assert(std::endian::native == std::endian::little,
              "the playback file is little-endian and mapped as is");

inline constexpr char kMagic[8] = {'H', 'A', 'P', 'S', 'P', 'L', 'A', 'Y'};
// 3: displacement slopes, 4: clearance, 5: midpoint forces, 6: midpoint stiffness, 7: midpoint
// displacements, 8: the change bound of the half cells' second-order cross derivatives,
// 9: refined cells, 10: the certificate, 11: refined cells' eighth-spacing points, 12: the depth
// model's quadratic term and the rest triangles near the onset (sections 24-26), 13: refined
// cells' sixteenth-spacing points (section 27)
inline constexpr std::uint32_t kVersion = 13;
inline constexpr std::uint64_t kAlignment = 64;

struct FileHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t header_bytes;  // sizeof(FileHeader)
  std::uint64_t file_size;     // bytes of the whole file
  std::uint64_t section_table_offset;
  std::uint32_t section_count;
  std::uint32_t section_entry_bytes;     // sizeof(SectionEntry)
  std::uint64_t section_table_checksum;  // XXH64 of the section table
  std::uint64_t header_checksum;         // XXH64 of the bytes before this field
  std::uint64_t reserved;
};
static_assert(sizeof(FileHeader) == 64);

enum class SectionId : std::uint32_t {
  kMeta = 1,              // one Meta
  kCheckpoints = 2,       // int32 [first configuration, count] per grid point (x-major: i, j, k)
  kConfigCheckpoint = 3,  // int32 grid point per configuration
  kConfigLevel = 4,       // int32 level per configuration
  kForce = 5,             // float64 x 3 per configuration, N
  kStiffness = 6,         // float64 x 9 per configuration, row-major, N per mesh unit
  kTransitions = 7,       // int32 x 26 per configuration: target, or a TransitionCode
  kViewNodes = 8,         // int32 mesh node per view node
  kReference = 9,         // float32 x 3 per view node, mesh units
  kTriangles = 10,        // int32 x 3 per surface triangle, view-node indices
  kDisplacements = 11,    // float32 x 3 per view node per configuration, mesh units
  kConfigZero = 12,       // int32 per configuration: 1 for a zero configuration (the body at rest)
  // float32 per configuration: 3 arrays (probe axis x, y, z) of 3 per view node, d u / d p,
  // dimensionless; empty when Meta::has_displacement_slopes is 0.
  kDisplacementSlopes = 13,
  // float64 x 4 per grid point (contact; empty for grab): the sphere's clearance from the body
  // at rest there (mesh units, > 0 clear) and its gradient (docs/playback.md, "Contact onset").
  kClearance = 14,
  // OnsetCorner per configuration (contact; empty for grab): its depth model, and for a free
  // check-point beside the contact onset its secant model (docs/playback.md, "Contact onset").
  kOnset = 15,
  // float64 x 3 x kMidpointDirections per configuration, N: the force felt half-way through its
  // move in each of the kMidpointOffsets directions, NaN where none was solved (docs/playback.md,
  // "Between the check-points"); empty when the state space recorded none.
  kMidpointForce = 16,
  // float64 x 9 x kMidpointDirections per configuration, N per mesh unit, row-major: the haptic
  // stiffness at the same points, NaN where none was solved; empty when the state space
  // recorded none (the cursor then fits bubbles to the midpoint forces instead).
  kMidpointStiffness = 17,
  // int32 per configuration: bit d set where the displacements half-way through its move in
  // direction kMidpointOffsets[d] are stored (section 19); empty when none are.
  kMidpointDisplacementMask = 18,
  // float32 per configuration, per midpoint direction d: the displacements (3 per view node,
  // mesh units), then their slopes along probe axis x, y, z (3 arrays of 3 per view node,
  // dimensionless): 12 x kMidpointDirections per view node; zero where the mask bit is clear;
  // empty with the mask.
  kMidpointDisplacements = 19,
  // int32 x kRefinedCellInts per configuration: the refined cell whose lowest corner it is (an
  // index into section 21, -1: none) and that cell's constrained faces and edges (kRefinedFace,
  // kRefinedEdge bits); then its eighth-spacing lattice (an index into section 23, -1: none) and
  // the faces and edges where that lattice is constrained; then its sixteenth-spacing lattice (an
  // index into section 27, -1: none) and its constrained faces and edges; empty when no cell is
  // refined.
  kRefinedCells = 20,
  // float64 x 12 x kRefinedPoints per refined cell: at each point of the cell's quarter-spacing
  // lattice (25 i + 5 j + k), the force (N) and the haptic stiffness (row-major, N per mesh unit);
  // NaN where none was solved (the corners and the moves' midpoints, a failed solve).
  kRefinedPoints = 21,
  // One CertificateRecord: what hapstate-certify measured on this file (docs/certificate.md);
  // empty until it has run (hapstate-index writes it empty).
  kCertificate = 22,
  // float64 x 12 x kEighthPoints per refined cell of depth 2: at each point of the cell's
  // eighth-spacing lattice (81 i + 9 j + k), the force and the haptic stiffness as in section 21;
  // NaN where none was solved (the quarter-spacing lattice's points, a failed solve).
  kEighthPoints = 23,
  // float64 x 9 per triangle (contact, frictionless): the corners of the rest surface's triangles
  // near the contact onset, mesh units; the cursor measures the sphere's clearance from them
  // exactly in a cell that has a list in section 25 (docs/playback.md, "Contact onset"); empty:
  // none (grab, sticking, or a sphere smaller than 3/4 of the spacing).
  kOnsetTriangles = 24,
  // int32 per grid point, plus one: where the list of the cell whose lowest corner it is starts
  // in section 26 (the next entry: where it ends; an empty list: the cursor interpolates the
  // clearance); empty with section 24.
  kOnsetCells = 25,
  // int32: the cells' lists of triangles (indices into section 24).
  kOnsetTriangleList = 26,
  // float64 x 12 x kSixteenthPoints per refined cell of depth 3: at each point of the cell's
  // sixteenth-spacing lattice (289 i + 17 j + k), the force and the haptic stiffness as in
  // section 21; NaN where none was solved (the eighth-spacing lattice's points, the eighth cells
  // the refine stage did not flag, a failed solve).
  kSixteenthPoints = 27,
};
inline constexpr int kSectionCount = 27;

// The band above the contact onset, in units of the smallest spacing, over which the cursor
// blends the force from the depth model into the interpolated force (docs/playback.md).
inline constexpr double kOnsetBandSpacings = 0.5;
// The band's width, mesh units, for a grid of these spacings.
inline double onset_band(const double* spacing) {
  return kOnsetBandSpacings * std::min({spacing[0], spacing[1], spacing[2]});
}

// A refined cell's lattice: 5 points per axis at quarter spacings.
inline constexpr int kRefinedPoints = 125;
// Its eighth-spacing lattice (refinement depth 2): 9 points per axis.
inline constexpr int kEighthPoints = 729;
// Its sixteenth-spacing lattice (refinement depth 3): 17 points per axis.
inline constexpr int kSixteenthPoints = 4913;
// Section 20's values per configuration: quarter slot, its constraints, eighth slot, its
// constraints, sixteenth slot, its constraints.
inline constexpr int kRefinedCellInts = 6;
// Constraint bits of a refined cell (section 20): face (axis a, side s) at bit 2 a + s; the edge
// along axis a at side s1 of the next axis (a + 1) % 3 and s2 of the one after at bit
// 6 + 4 a + 2 s1 + s2. A constrained face or edge borders a cell that is not refined: the cursor
// interpolates there as that cell does (docs/playback.md, "Refined cells"). The eighth-spacing
// lattice's bits mean the same for a neighbour without an eighth-spacing lattice, the sixteenth-
// spacing lattice's for one without a sixteenth-spacing lattice.
constexpr int refined_face_bit(int axis, int side) { return 2 * axis + side; }
constexpr int refined_edge_bit(int axis, int side1, int side2) {
  return 6 + 4 * axis + 2 * side1 + side2;
}

// The directions whose moves record the force half-way (offsets all >= 0): per configuration,
// one edge, face and cell of the grid seen from their lowest corner.
inline constexpr int kMidpointDirections = 7;
inline constexpr int kMidpointOffsets[kMidpointDirections][3] = {
    {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
// The index into kMidpointOffsets of grid offset (di, dj, dk), or -1 if it is not one of them.
constexpr int midpoint_direction(int di, int dj, int dk) {
  for (int d = 0; d < kMidpointDirections; ++d)
    if (kMidpointOffsets[d][0] == di && kMidpointOffsets[d][1] == dj &&
        kMidpointOffsets[d][2] == dk)
      return d;
  return -1;
}

struct SectionEntry {
  std::uint32_t id;             // SectionId
  std::uint32_t element_bytes;  // size of one element (for readers that skip sections)
  std::uint64_t offset;         // from the start of the file, multiple of kAlignment
  std::uint64_t bytes;
  std::uint64_t checksum;  // XXH64 of the section's bytes
};
static_assert(sizeof(SectionEntry) == 32);

// A configuration's data for the contact onset (docs/playback.md, "Contact onset"), with d the
// sphere's depth into the body at rest at its check-point (minus the clearance).
// - The depth model f(x) = x (per_depth + per_depth_squared x) at depth x: a touching
//   configuration deeper than 1e-3 of a spacing passes through its force f at its depth d with
//   its stiffness's slope along the depth (as far as it lies along f, limited: onset_model.cc);
//   and the displacements per unit depth, displacement_per_depth x those of configuration
//   depth_source: its own (depth_source itself, factor 1 / d). A zero configuration at a free
//   check-point, or a touching one shallower than that: the mean model of the deeper touching
//   configurations its transitions lead to (the nearest grid distance that has any) and the
//   displacements of the first of them (model 0, factor 0 if none).
//   depth_source = -1: none (a touching configuration clear of the rest body, a state that
//   depends on the path).
// - The secant model (source >= 0: a free check-point's zero configuration with such
//   neighbours): as a cell corner next to the onset it holds their force in proportion to the
//   depth extended to it, force q d, stiffness q (grad d)^T (q = f / d of each, averaged), and the
//   displacements secant[0] x those of configuration `source`, their slope along axis a secant[1 +
//   a] x them (per mesh unit).
struct OnsetCorner {
  double force[3];      // N
  double stiffness[9];  // N per mesh unit, row-major
  double secant[4];
  double per_depth[3];          // N per mesh unit
  double per_depth_squared[3];  // N per mesh unit^2
  double displacement_per_depth;
  std::int32_t source;
  std::int32_t depth_source;
};
static_assert(sizeof(OnsetCorner) == 192);

// Section 22: the certificate's headline numbers, per scheme [trilinear, Hermite] (the order
// of hapstate::Scheme). measured_source_hash is the source hash of the file it was measured on,
// measured_code_id the id of the playback code that measured it (playback/code_id.h; 0 in files
// certified before it was recorded): a reader ignores a record whose hash is not this file's
// Meta::source_hash or whose code id is not its own (another cursor promises nothing of it).
struct CertificateRecord {
  std::uint64_t measured_source_hash;
  std::int32_t paths, steps_per_path, steps, failed_steps;
  double force_error_worst[2], force_error_p99[2];  // of the path's largest force
  double force_error_worst_n[2];                    // N
  double deformation_error_worst[2];
  double stiffness_n_per_mm;
  double query_median_ns, query_p999_ns;
  std::uint64_t measured_code_id;
  double reserved;  // zero
};
static_assert(sizeof(CertificateRecord) == 128);

// Transition table entries that are not a configuration index.
enum TransitionCode : std::int32_t {
  kUndecided = -1,    // not computed (the source was not expanded)
  kOutsideGrid = -2,  // the neighbour is not a check-point of the workspace
  kFailed = -3,       // the solve failed
};

enum class ProbeModeCode : std::int32_t { kGrab = 0, kContact = 1 };

struct Meta {
  double origin[3];           // position of grid index (0, 0, 0), mesh units
  double spacing[3];          // mesh units, > 0
  double rest_position[3];    // probe at rest, mesh units
  double max_force;           // N
  double unit;                // metres per mesh unit
  double force_change_bound;  // N per mesh unit (docs/playback.md)
  // N: the largest correction (per component) of an edge's, a face's and a cell's bubble
  // (playback/cell_bubbles.h); all 0 when kMidpointForce is empty.
  double bubble_limit[3];
  // N per mesh unit: the largest |entry| of any stored stiffness (configurations and midpoints);
  // the cursor clamps the stiffness it fits at a midpoint to it. 0 without kMidpointStiffness.
  double stiffness_limit;
  std::int32_t lo[3];       // grid index of the first grid point per axis
  std::int32_t dims[3];     // grid points per axis, >= 1
  std::int32_t probe_mode;  // ProbeModeCode
  std::int32_t rest_configuration;
  std::int32_t num_configurations;
  std::int32_t num_view_nodes;
  std::int32_t num_mesh_nodes;
  std::int32_t num_triangles;
  std::int32_t view_all_nodes;           // 1: view nodes are every mesh node in order
  std::int32_t has_displacement_slopes;  // 1: kDisplacementSlopes holds every configuration's
  std::uint64_t scene_hash;              // XXH64 of the scene text
  std::uint64_t source_hash;             // of what the index was built from (hapstate-index skips)
  double contact_radius;                 // mesh units, with section 24; else 0
};

// What is wrong with the sizes of sections 24-26 (nullptr: nothing; O(1), checked at open):
// `triangle_doubles` 9 each, `num_cells` the grid points + 1, the list; all empty (and no contact
// radius), or the triangles and cells filled with a contact radius > 0.
inline const char* onset_sizes_problem(std::size_t triangle_doubles, std::size_t num_cells,
                                       std::size_t list_size, std::int64_t points, double radius) {
  if (triangle_doubles == 0 && num_cells == 0 && list_size == 0)
    return radius == 0 ? nullptr : "a contact radius without onset triangles";
  if (triangle_doubles == 0 || triangle_doubles % 9 != 0 ||
      num_cells != static_cast<std::size_t>(points) + 1)
    return "onset triangle or cell table size";
  if (!(radius > 0) || !std::isfinite(radius)) return "onset triangles without a contact radius";
  return nullptr;
}

// What is wrong with the contents of sections 24-26 (nullptr: nothing; the writer and verify()):
// the sizes, then `cells` (starts from 0, not decreasing, the last the list's length) and `list`
// (indices into the triangles), and every corner finite.
inline const char* onset_lists_problem(const double* triangles, std::size_t triangle_doubles,
                                       const std::int32_t* cells, std::size_t num_cells,
                                       const std::int32_t* list, std::size_t list_size,
                                       std::int64_t points, double radius) {
  if (const char* p = onset_sizes_problem(triangle_doubles, num_cells, list_size, points, radius))
    return p;
  if (num_cells == 0) return nullptr;
  if (cells[0] != 0 || static_cast<std::size_t>(cells[num_cells - 1]) != list_size)
    return "onset cell lists do not cover the list";
  for (std::size_t k = 1; k < num_cells; ++k)
    if (cells[k] < cells[k - 1]) return "onset cell lists out of order";
  const std::size_t count = triangle_doubles / 9;
  for (std::size_t k = 0; k < list_size; ++k)
    if (list[k] < 0 || static_cast<std::size_t>(list[k]) >= count)
      return "an onset triangle index is out of range";
  for (std::size_t k = 0; k < triangle_doubles; ++k)
    if (!std::isfinite(triangles[k])) return "an onset triangle corner is not finite";
  return nullptr;
}

// Whether a cell of a contact file may blend in the depth model near the onset, and whether it is
// clear of the rest body, from the shallowest and the deepest depth (minus the clearance) of its
// corners: blend where the sphere may be shallower than the band (some corner within the band
// plus a cell diagonal of the onset: the clearance changes by at most the distance); clear where
// every corner is clear by a diagonal (then every point of the cell is). One rule for the cursor
// (prepare_onset) and hapstate-index (which cells get rest triangles).
struct OnsetCellTest {
  bool blend = false, clear = false;
};
inline OnsetCellTest onset_cell_test(double shallowest, double deepest, const double* spacing) {
  const double diagonal =
      std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
  return {shallowest <= onset_band(spacing) + diagonal, -deepest >= diagonal};
}

// The grid-point numbering of the file (x-major: i slowest, k fastest; docs/playback.md): the
// linear index of grid point ijk (absolute grid indices), or -1 outside the grid.
inline std::int32_t grid_point_index(const Meta& m, const std::array<std::int32_t, 3>& ijk) {
  std::int32_t g = 0;
  for (int a = 0; a < 3; ++a) {
    const std::int32_t i = ijk[a] - m.lo[a];
    if (i < 0 || i >= m.dims[a]) return -1;
    g = g * m.dims[a] + i;
  }
  return g;
}
// Its inverse; a g out of range (a damaged file) gives the first grid point, so that callers
// stay defined.
inline std::array<std::int32_t, 3> grid_point_ijk(const Meta& m, std::int64_t g) {
  const std::int64_t points = std::int64_t(m.dims[0]) * m.dims[1] * m.dims[2];
  if (g < 0 || g >= points) g = 0;
  const std::int64_t yz = std::int64_t(m.dims[1]) * m.dims[2];
  return {m.lo[0] + static_cast<std::int32_t>(g / yz),
          m.lo[1] + static_cast<std::int32_t>((g / m.dims[2]) % m.dims[1]),
          m.lo[2] + static_cast<std::int32_t>(g % m.dims[2])};
}
// Grid index of the last cell's first corner along axis a: a cell spans [base, base + 1]; with a
// single check-point along an axis the cell is degenerate there (s = 0 always).
inline std::int32_t last_cell(const Meta& m, int a) {
  return m.lo[a] + (m.dims[a] > 1 ? m.dims[a] - 2 : 0);
}
static_assert(sizeof(Meta) == 208);

}  // namespace hapstate::playback
