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
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace hapstate {
namespace playback {
class CursorCore;
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
  // The certificate's headline numbers, once hapstate-certify has measured this file with this
  // version of the playback code (a file hapstate-index writes anew has none until then, nor has
  // a file certified by another version: its cursor may interpolate differently).
  std::optional<PlaybackCertificate> certificate() const;

  struct Impl;  // the mapping's typed sections (playback/file_impl.h)

 private:
  friend class playback::CursorCore;
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
  // Hermite in a refined contact cell: the point of the cell (0..1 per axis) near the probe where
  // the half cells' force is the refined force; deform() interpolates the nodes farther than 4
  // radii from the probe there, those within 2 at cell_position, and blends between (the body's
  // sway follows the force, its dent the sphere: docs/playback.md, "Refined cells"). Elsewhere
  // cell_position (a snapshot built by hand sets it so; deform() ignores one outside the cell or
  // farther than a quarter of the smallest spacing from cell_position).
  std::array<double, 3> sway_position{};
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
  ~HapticCursor();
  HapticCursor(const HapticCursor&) = delete;
  HapticCursor& operator=(const HapticCursor&) = delete;

  void reset();  // the probe at rest, every corner from the rest configuration
  // The probe placed at `probe` with the body at rest (contact probe: the device starts away
  // from the body): anchored at the zero configuration nearest to `probe` (grab probe: only
  // the rest configuration is one), from where the next force() call walks. Scans the grid:
  // call it before the haptic loop, not in it.
  void reset(const std::array<double, 3>& probe);
  Force force(const std::array<double, 3>& probe);
  void set_scheme(Scheme scheme);  // each scheme fits the cell its own way at the next force()
  Scheme scheme() const;

  // The configuration at the check-point nearest to the last probe position (-1 if that
  // corner is extended), and that check-point's grid index.
  std::int32_t anchor_configuration() const;
  std::array<std::int32_t, 3> anchor_checkpoint() const;
  CornerSource corner_source(int corner) const;
  // The stored configuration at a corner (0..7, bits i j k), -1 if extended.
  std::int32_t corner_configuration(int corner) const;
  // Cells entered since creation (a measure of the walk).
  std::uint64_t cells_walked() const;

  void snapshot(Snapshot* out) const;  // the newest published state

 private:
  // The cell, its fitted interpolants and the snapshot buffer (about 130 KiB), made once here
  // (playback/cursor_core.h).
  std::unique_ptr<playback::CursorCore> core_;
};

// Vertex positions of the view nodes for a snapshot: reference + interpolated displacements
// (the snapshot's scheme; Hermite needs the file's displacement slopes, else trilinear).
// `out` holds 3 * num_view_nodes() floats. No allocation.
void deform(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out);
// The interpolated displacements only (3 per view node, mesh units).
void displacements(const PlaybackFile& file, const Snapshot& snapshot, std::span<float> out);

}  // namespace hapstate
