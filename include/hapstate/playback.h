// hapstate playback runtime: the public C++ interface (docs/playback.md). Link hapstate::playback
// (no SQLite, HDF5 or solver needed). A C interface for other languages: hapstate/playback_c.h.
//
//   hapstate::PlaybackFile file("state/playback.bin");      // mmap + O(1) checks
//   hapstate::HapticCursor cursor(file, hapstate::Scheme::kHermite);
//   haptic thread, 1 kHz:  Force f = cursor.force(p);       // no allocation, lock or syscall
//   visual thread, 60 Hz:  cursor.snapshot(&s); hapstate::deform(file, s, positions);
//
// Positions are in mesh units (the scene's), forces in N, stiffness in N per mesh unit.
#pragma once

#include "hapstate/error.h"

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

namespace hapstate {
namespace playback {
struct OnsetCorner;
}

struct Snapshot;

// Interpolation of the force over the 8 corners of the probe's grid cell, and, where the file
// holds them, the forces recorded half-way between them (docs/playback.md, "Between the
// check-points").
enum class Scheme : std::int32_t {
  kTrilinear = 0,  // the paper's: trilinear weights (on the half-spacing lattice with midpoints)
  kHermite = 1,    // cubic Hermite per axis: corner forces and their stiffness (derivatives)
};

// Where a corner's data came from (docs/playback.md, "missing corners").
enum class CornerSource : std::int8_t {
  kStored = 0,    // a stored configuration
  kExtended = 1,  // none stored or reachable: extended from the neighbouring corner's force
                  // and stiffness (first-order Taylor), carried while the cursor stays near
};

// What hapstate-certify measured on a playback file (docs/certificate.md): the paper's
// experiment on `paths` seeded random paths over the workspace. Arrays are indexed by Scheme
// ([0] trilinear, [1] Hermite); force errors are |f - f*| over the path's largest |f*|.
struct PlaybackCertificate {
  int paths = 0, steps_per_path = 0, steps = 0, failed_steps = 0;
  std::array<double, 2> force_error_worst{}, force_error_p99{};
  std::array<double, 2> force_error_worst_n{};  // N
  std::array<double, 2> deformation_error_worst{};
  double stiffness_n_per_mm = 0;                  // the largest stored stiffness (|eigenvalue|)
  double query_median_ns = 0, query_p999_ns = 0;  // the Hermite force() call where it was measured
};

// A read-only, memory-mapped playback file written by hapstate-index.
class PlaybackFile {
 public:
  // Maps `file`. Checks in O(1): magic, version, header checksum, file size, section table
  // (its checksum, every section inside the file, 64-byte aligned, of the size the header
  // implies). Throws hapstate::InputError (hapstate/error.h) naming the file and what is wrong
  // when the file is missing or not a usable playback file, hapstate::EnvironmentError when it
  // cannot be read or mapped (permissions, I/O, memory); both are std::runtime_error.
  explicit PlaybackFile(const std::filesystem::path& file);
  ~PlaybackFile();
  PlaybackFile(const PlaybackFile&) = delete;
  PlaybackFile& operator=(const PlaybackFile&) = delete;

  // Checks every section's checksum and the cross-references (indices in range, finite
  // numbers). Throws std::runtime_error naming the file and the section on the first problem.
  void verify() const;

  const std::filesystem::path& path() const { return path_; }
  std::int32_t num_configurations() const;
  std::int32_t num_view_nodes() const;  // nodes whose displacements are stored
  std::int32_t num_mesh_nodes() const;
  bool view_is_all_nodes() const;  // view nodes = every mesh node, in mesh order
  bool is_contact() const;         // the scene's probe is a contact sphere
  // Whether configuration c is a zero configuration: the body at rest (no force; no
  // displacement, or under gravity the loaded rest state's); the rest configuration, and with a
  // contact probe every free check-point's.
  bool is_zero_configuration(std::int32_t c) const;
  std::span<const std::int32_t> view_nodes() const;    // mesh node index per view node
  std::span<const float> reference_positions() const;  // 3 per view node, mesh units
  std::span<const std::int32_t> triangles() const;     // 3 view-node indices each
  std::array<double, 3> rest_position() const;         // probe at rest, mesh units
  std::array<double, 3> grid_origin() const;
  std::array<double, 3> grid_spacing() const;
  std::array<std::int32_t, 3> grid_lo() const;    // index of the first check-point
  std::array<std::int32_t, 3> grid_dims() const;  // check-points per axis
  double max_force() const;                       // the device limit F_max, N
  // Documented bound on the change of the force between two probe positions:
  // |f(p) - f(q)| <= force_change_bound() * |p - q| for any cursor (docs/playback.md).
  double force_change_bound() const;

  // Force and stiffness of configuration c (0 <= c < num_configurations()).
  std::array<double, 3> force(std::int32_t c) const;
  std::array<double, 9> stiffness(std::int32_t c) const;       // row-major d(force)/d(probe)
  std::span<const float> displacements(std::int32_t c) const;  // 3 per view node, mesh units
  // Whether the file holds every configuration's displacement slopes d u / d p (hapstate-index
  // of a state expanded by this version; without them Hermite deformation is trilinear).
  bool has_displacement_slopes() const;
  // The slopes of configuration c along probe axis a (0..2): 3 per view node, dimensionless.
  // Empty if the file has none.
  std::span<const float> displacement_slopes(std::int32_t c, int axis) const;
  // The transition table entry of configuration c in direction d (0..25, numbered as in
  // docs/state-space.md): the target configuration, or -1 undecided, -2 outside the grid,
  // -3 failed (docs/playback.md).
  std::int32_t transition_entry(std::int32_t c, int d) const;
  std::uint64_t scene_hash() const;   // XXH64 of the scene text the file was built from
  std::uint64_t source_hash() const;  // of what hapstate-index built it from
  // The certificate's headline numbers, once hapstate-certify has measured this file (a file
  // hapstate-index writes anew has none until then).
  std::optional<PlaybackCertificate> certificate() const;

  struct Impl;  // the mapping's typed sections (playback/file_impl.h)

 private:
  friend class HapticCursor;
  friend void deform(const PlaybackFile&, const Snapshot&, std::span<float>);
  friend void displacements(const PlaybackFile&, const Snapshot&, std::span<float>);
  const Impl& impl() const { return *impl_; }

  std::filesystem::path path_;
  Impl* impl_ = nullptr;
};

// What the visual thread needs of a cursor: the corner configurations of its cell, the probe's
// place in the cell and the scheme (deform() interpolates the displacements as the cursor
// interpolates the force: trilinear, or cubic Hermite from the corners' displacement slopes).
struct Snapshot {
  std::uint64_t sequence = 0;                          // force() calls so far (0: none yet)
  std::array<double, 3> probe{};                       // mesh units
  std::array<double, 3> force{};                       // N, as returned by force()
  std::array<std::int32_t, 8> corner_configuration{};  // displacement source, -1: zero
  std::array<double, 8> weight{};                      // trilinear weights of the corners
  std::array<double, 3> cell_position{};               // the probe in its cell, 0..1 per axis
  // Grid offset of each corner from its displacement source's check-point (non-zero for an
  // extended corner: its displacements are extended from the source's by its slopes).
  std::array<std::array<std::int32_t, 3>, 8> corner_shift{};
  Scheme scheme = Scheme::kTrilinear;
  // The corners that are free check-points beside the contact onset, in a cell near it (bit c;
  // docs/playback.md, "Contact onset"): their displacements are secant[c][0] x those of
  // corner_configuration[c], their slope along axis a secant[c][1 + a] x them (per mesh unit).
  std::int32_t secant_corners = 0;
  std::array<std::array<double, 4>, 8> secant{};
  // Just past the contact onset the displacements are (1 - onset_weight) x the interpolation
  // above + onset_weight x onset_depth x sum_c weight[c] per_depth[c] x (the displacements of
  // depth_source[c]): the depth model (docs/playback.md, "Contact onset").
  double onset_weight = 0;
  double onset_depth = 0;
  std::array<double, 8> per_depth{};
  std::array<std::int32_t, 8> depth_source{};
  // Hermite, per point of the cell's half-spacing lattice (index 9 x + 3 y + z, each 0..2 in
  // half spacings): 0, or 1 + the index (configuration x kMidpointDirections + direction) of
  // the stored midpoint whose displacements and slopes hold there; with any set, deform()
  // interpolates each half-spacing cell as the cursor does the force (docs/playback.md).
  std::array<std::int32_t, 27> midpoint{};
  // Near the contact onset, per lattice point with a midpoint code: the onset blend there,
  // {R, dR/d(depth), depth, d(depth)/dx, d/dy, d/dz} (depth in mesh units, its gradient per
  // mesh unit), through which deform() fits the stored displacements as the cursor fits the
  // force; R = 0 where no blend applies (the stored displacements as they are).
  std::array<std::array<double, 6>, 27> midpoint_blend{};
};

// Result of one haptic query.
struct Force {
  std::array<double, 3> value{};  // N
  // d(value)/d(probe), row-major, N per mesh unit (docs/playback.md, "Stiffness"): the exact
  // derivative of the Hermite interpolant; the trilinear blend of the corners' stiffness with
  // kTrilinear and outside the grid. At a check-point, the stored configuration's stiffness.
  std::array<double, 9> stiffness{};
  bool inside_grid = true;  // false: the probe was outside the grid (extended force)
};

// The haptic cursor of one haptic thread (docs/playback.md). Keeps the configurations of the
// 8 corners of the probe's cell, anchored at the rest configuration when created or reset,
// and follows the stored transitions cell by cell as the probe moves. force() allocates
// nothing, takes no lock and makes no system call. snapshot() may be called from one other
// thread (the visual thread) at any time: a wait-free triple buffer.
class HapticCursor {
 public:
  explicit HapticCursor(const PlaybackFile& file, Scheme scheme = Scheme::kHermite);

  void reset();  // the probe at rest, every corner from the rest configuration
  // The probe placed at `probe` with the body at rest (contact probe: the device starts away
  // from the body): anchored at the zero configuration nearest to `probe` (grab probe: only
  // the rest configuration is one), from where the next force() call walks. Scans the grid:
  // call it before the haptic loop, not in it.
  void reset(const std::array<double, 3>& probe);
  Force force(const std::array<double, 3>& probe);
  void set_scheme(Scheme scheme) {
    scheme_ = scheme;
    fitted_ = false;  // each scheme fits its own
  }
  Scheme scheme() const { return scheme_; }

  // The configuration at the check-point nearest to the last probe position (-1 if that
  // corner is extended), and that check-point's grid index.
  std::int32_t anchor_configuration() const;
  std::array<std::int32_t, 3> anchor_checkpoint() const;
  CornerSource corner_source(int corner) const { return corners_[corner].source; }
  // The stored configuration at a corner (0..7, bits i j k), -1 if extended.
  std::int32_t corner_configuration(int corner) const { return corners_[corner].configuration; }
  // Cells entered since creation (a measure of the walk).
  std::uint64_t cells_walked() const { return cells_walked_; }

  void snapshot(Snapshot* out) const;  // the newest published state

  struct Corner {
    std::int32_t configuration = -1;      // stored configuration, -1 if extended
    std::int32_t displacement = -1;       // configuration whose displacements are shown, -1: zero
    std::array<std::int32_t, 3> shift{};  // grid offset from that configuration's check-point
    CornerSource source = CornerSource::kExtended;
    std::array<double, 3> force{};
    std::array<double, 9> stiffness{};
    // Contact: the configuration's onset data in the file (playback::OnsetCorner; nullptr:
    // none, as for an extended corner), used in a cell near the onset: `secant` a free
    // check-point beside it with a secant model, `depth_model` one with a depth model (their
    // configuration indices checked).
    const playback::OnsetCorner* onset = nullptr;
    bool secant = false;
    bool depth_model = false;
  };

 private:
  // The cell's Hermite interpolant as a tensor product: per axis 4 bases (index 2 o + k, o the
  // corner side, k 0 the value and 1 the derivative basis), coefficients [x][y][r][z] for force
  // component r: a corner's force (k = 000), stiffness columns (one k = 1) and cross
  // derivatives (two k = 1); zero for k = 111.
  using CellCoefficients = std::array<std::array<std::array<std::array<double, 4>, 3>, 4>, 4>;
  void update_coefficients();
  Corner stored_corner(std::int32_t configuration) const;
  void prepare_onset();
  void anchor_at(std::int32_t configuration);
  void enter_cell(const std::array<std::int32_t, 3>& base);
  void resolve_corner(int corner, const std::array<Corner, 8>& old,
                      const std::array<std::int32_t, 3>& old_base);
  void walk_to(const std::array<double, 3>& q);
  struct OnsetBlend {
    bool at_rest = false;  // the sphere clear of the rest body: force and displacements 0
    double weight = 0;     // of the depth model
    double depth = 0;
  };
  OnsetBlend apply_onset(const double (&B)[3][4], const double (&dB)[3][4],
                         const std::array<double, 3>& s, std::array<double, 3>* value,
                         std::array<double, 9>* slope) const;
  void per_depth_at(const std::array<double, 3>& t, double (&q)[3], double (&dq)[3][3]) const;
  double clearance(const double (&B)[3][4], const double (&dB)[3][4], double (&grad)[3]) const;
  struct OnsetPoint {
    double R = 0, dR = 0, depth = 0;  // the blend's weight, its derivative by the depth
    double grad[3] = {};              // the clearance's gradient
  };
  bool onset_blend_at(const std::array<double, 3>& t, OnsetPoint* out) const;
  bool onset_target(const std::array<double, 3>& t, const OnsetPoint& o, const double* felt,
                    const double* felt_k, double* out, double* out_k) const;
  void publish(const std::array<double, 3>& probe, const Force& f, const std::array<double, 3>& s,
               const OnsetBlend& onset);

  const PlaybackFile& file_;
  Scheme scheme_;
  std::array<std::int32_t, 3> base_{};  // grid index of corner 0 of the current cell
  std::array<Corner, 8> corners_{};     // corner c at base + ((c>>2)&1, (c>>1)&1, c&1)
  CellCoefficients coef_{};             // of corners_, updated whenever they change
  // The cell's bubble corrections toward the force recorded half-way through the corners'
  // moves, N per component (docs/playback.md, "Between the check-points"), fitted at the first
  // Hermite call in a cell, and grouped by shape for force().
  std::array<std::array<double, 3>, 19> bubble_{};
  double bubble_edge_[3][3][2][2] = {};  // [axis][component][side o1][side o2]
  double bubble_face_[3][3][2] = {};     // [normal][component][side]
  double bubble_cell_[3] = {};
  int num_bubbles_ = 0;   // non-zero corrections
  bool fitted_ = false;   // the midpoint data of this cell (bubbles or lattice) are fitted
  bool lattice_ = false;  // Hermite with the midpoint stiffness: 8 half-spacing Hermite cells
  std::array<CellCoefficients, 8> half_coef_{};  // their coefficients (bits x y z as corners)
  bool refined_ = false;                         // a refined cell: 64 quarter-spacing Hermite cells
  std::array<CellCoefficients, 64> quarter_coef_{};  // their coefficients, (4 x + y) 4 + z
  // A refined cell with kTrilinear: the force and the stiffness (row-major) at the 125 points of
  // its quarter-spacing lattice, 25 i + 5 j + k, interpolated trilinearly on each quarter cell.
  std::array<std::array<double, 12>, 125> quarter_trilinear_{};
  std::array<std::int32_t, 27> midpoint_code_{};            // Snapshot::midpoint of this cell
  std::array<std::array<double, 6>, 27> midpoint_blend_{};  // Snapshot::midpoint_blend
  std::uint64_t blend_generation_ = 0;  // changes with midpoint_blend_ (copied to a slot then)
  int recorded_midpoint(int k, double* force, double* stiffness) const;
  struct MidpointTarget;  // what the cell's fit aims at a midpoint (cursor.cc)
  void fit_cell();
  void midpoint_target(int k, MidpointTarget* out) const;
  void fit_cell_lattice(const MidpointTarget* targets);
  std::int32_t refined_cell() const;
  void fit_refined_cell(std::int32_t slot);
  bool refined_target(const int (&p)[3], const double* data, double* out) const;
  void fit_refined_trilinear(std::int32_t slot);
  void trilinear_at(const std::array<double, 3>& s, double* value, double* stiffness) const;
  void find_midpoint_displacements(const MidpointTarget* targets);
  void fit_cell_bubbles(const MidpointTarget* targets);
  void add_bubbles(const double (&m)[3], const double (&dm)[3], const double (&v)[3][2],
                   const double (&dv)[3][2], std::array<double, 3>* value,
                   std::array<double, 9>* slope) const;
  // Contact: every corner has a depth model and the sphere may be shallower than the blending
  // band somewhere in the cell (docs/playback.md, "Contact onset").
  bool onset_ = false;
  bool clear_cell_ = false;  // onset_ and the sphere clear of the rest body in the whole cell
  std::array<std::array<std::array<double, 4>, 4>, 4> clearance_coef_{};  // [x][y][z]
  std::array<std::array<double, 3>, 8> per_depth_{};  // the corners' force per unit depth
  // The force and stiffness of corner c as interpolated: the secant model's in a cell near the
  // onset (onset_), else the stored ones.
  const double* force_of(int c) const;
  const double* stiffness_of(int c) const;
  std::array<double, 3> last_q_{};  // last probe position, grid units, clamped to the grid
  std::uint64_t calls_ = 0;
  std::uint64_t cells_walked_ = 0;

  Snapshot slots_[3];  // triple buffer: back (writer), middle, front (reader)
  std::uint64_t slot_blend_generation_[3] = {};
  std::uint32_t back_ = 0;
  mutable std::uint32_t front_ = 2;
  mutable std::atomic<std::uint32_t> middle_{1};  // slot index | kFresh
};

// Vertex positions of the view nodes for a snapshot: reference + interpolated displacements
// (the snapshot's scheme; Hermite needs the file's displacement slopes, else trilinear).
// `out` holds 3 * num_view_nodes() floats. No allocation.
void deform(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out);
// The interpolated displacements only (3 per view node, mesh units).
void displacements(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out);

}  // namespace hapstate
