// PRIVATE to the playback module: the state behind a HapticCursor (include/hapstate/playback.h),
// made once at its construction. Its rooms: cursor.cc (the haptic query), cursor_walk.cc (the
// cell walk and the cell's Hermite coefficients), cursor_onset.cc (the contact onset blend),
// cursor_midpoints.cc (the midpoint fit: half-spacing lattice or bubbles), cursor_refined.cc
// (refined cells), cursor_snapshot.cc (the triple buffer the visual thread reads). The shared
// cell arithmetic: cell_math.h, cell_lattice.h.
#pragma once

#include "hapstate/playback.h"
#include "playback/format.h"
#include "playback/lattice.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace hapstate::playback {

// The public methods are HapticCursor's (same meaning); the rest is the cursor's working state.
class CursorCore {
 public:
  CursorCore(const PlaybackFile& file, Scheme scheme);
  CursorCore(const CursorCore&) = delete;
  CursorCore& operator=(const CursorCore&) = delete;

  void reset();
  void reset(const std::array<double, 3>& probe);
  Force force(const std::array<double, 3>& probe);
  void set_scheme(Scheme scheme) {
    scheme_ = scheme;
    fitted_ = false;  // each scheme fits its own
  }
  Scheme scheme() const { return scheme_; }
  std::int32_t anchor_configuration() const;
  std::array<std::int32_t, 3> anchor_checkpoint() const;
  CornerSource corner_source(int corner) const { return corners_[corner].source; }
  std::int32_t corner_configuration(int corner) const { return corners_[corner].configuration; }
  std::uint64_t cells_walked() const { return cells_walked_; }
  void snapshot(Snapshot* out) const;

  struct Corner {
    std::int32_t configuration = -1;      // stored configuration, -1 if extended
    std::int32_t displacement = -1;       // configuration whose displacements are shown, -1: zero
    std::array<std::int32_t, 3> shift{};  // grid offset from that configuration's check-point
    CornerSource source = CornerSource::kExtended;
    std::array<double, 3> force{};
    std::array<double, 9> stiffness{};
    // Contact: the configuration's onset data in the file (OnsetCorner; nullptr:
    // none, as for an extended corner), used in a cell near the onset: `secant` a free
    // check-point beside it with a secant model, `depth_model` one with a depth model (their
    // configuration indices checked).
    const OnsetCorner* onset = nullptr;
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
  std::array<double, 3> locate(const std::array<double, 3>& probe, bool* inside,
                               std::array<double, 3>* clamped);
  void corner_blend(const std::array<double, 3>& s, std::array<double, 3>* value,
                    std::array<double, 9>* k) const;
  void lattice_trilinear_at(const std::array<double, 3>& s, int n,
                            const std::array<double, 12>* lattice, std::array<double, 3>* value,
                            std::array<double, 9>* k) const;
  void sub_cell_at(const std::array<double, 3>& s, int n, std::array<double, 3>* value,
                   std::array<double, 9>* slope) const;
  void bubbles_at(const std::array<double, 3>& s, const double (&B)[3][4], const double (&dB)[3][4],
                  std::array<double, 3>* value, std::array<double, 9>* slope) const;
  struct OnsetBlend {
    bool at_rest = false;  // the sphere clear of the rest body: force and displacements 0
    double weight = 0;     // of the depth model
    double depth = 0;
  };
  OnsetBlend apply_onset(const double (&B)[3][4], const double (&dB)[3][4],
                         const std::array<double, 3>& s, std::array<double, 3>* value,
                         std::array<double, 9>* slope) const;
  void depth_model_at(const std::array<double, 3>& t, double depth, const double (&grad)[3],
                      double (&model)[3], double (&dmodel)[3][3]) const;
  double clearance(const std::array<double, 3>& s, const double (&B)[3][4],
                   const double (&dB)[3][4], double (&grad)[3]) const;
  double interpolated_clearance(const double (&B)[3][4], const double (&dB)[3][4],
                                double (&grad)[3]) const;
  struct OnsetPoint {
    double R = 0, dR = 0, depth = 0;  // the blend's weight, its derivative by the depth
    double grad[3] = {};              // the clearance's gradient
  };
  bool onset_blend_at(const std::array<double, 3>& t, OnsetPoint* out) const;
  bool onset_target(const std::array<double, 3>& t, const OnsetPoint& o, const double* felt,
                    const double* felt_k, double* out, double* out_k) const;
  // s: the probe in its cell; shown: Snapshot::sway_position.
  void publish(const std::array<double, 3>& probe, const Force& f, const std::array<double, 3>& s,
               const std::array<double, 3>& shown, const OnsetBlend& onset);

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
  // A refined cell's lattice below the quarter-spacing one: N = 9, its eighth-spacing lattice
  // (refinement depth 2), N = 17, its sixteenth-spacing one (depth 3). Allocated at construction
  // when the file has any, used when deep_ (deeper_). Its points are fitted lazily, those a cell
  // of the lattice needs when the probe enters it (deep_point).
  template <int N>
  struct DeepCell {
    Lattice<N> lattice;   // Hermite: the data at its N^3 points
    bool exact[N][N][N];  // a point that keeps the coarser lattice's interpolant's data
    // Hermite, per point: 0 nothing yet, 1 value and gradient, 2 the gradient limited, 3 the
    // cross derivatives (deep_point).
    std::uint8_t stage[N][N][N];
    const double* stored = nullptr;  // the cell's solved points (section 23 or 27)
    std::int32_t constraints = 0;    // the lattice's constraint bits
    CellCoefficients coef;           // of sub-cell `sub`, fitted when the probe enters it
    int sub = -1;
    // kTrilinear: the force and the stiffness at its points, (N i + j) N + k, where ready.
    std::array<std::array<double, 12>, N * N * N> trilinear;
    bool trilinear_ready[N][N][N];
    // N = 9 with a sixteenth-spacing lattice: the coefficients of each eighth cell (64 i + 8 j +
    // k), fitted when a sixteenth-spacing point reads them (sub_ready). N = 17: per eighth cell,
    // 0 not yet known, 1 none of its 27 points has a solve of its own (the eighth cell's cubic is
    // the interpolant there), 2 some have.
    std::vector<CellCoefficients> sub_coef;
    std::vector<std::uint8_t> sub_ready;
  };
  std::unique_ptr<DeepCell<9>> eighth_;
  std::unique_ptr<DeepCell<17>> sixteenth_;
  bool deep_ = false;    // the refined cell has an eighth-spacing lattice, fitted into eighth_
  bool deeper_ = false;  // and a sixteenth-spacing one, fitted into sixteenth_
  std::array<std::int32_t, 27> midpoint_code_{};            // Snapshot::midpoint of this cell
  std::array<std::array<double, 6>, 27> midpoint_blend_{};  // Snapshot::midpoint_blend
  std::uint64_t blend_generation_ = 0;  // changes with midpoint_blend_ (copied to a slot then)
  int recorded_midpoint(int k, double* force, double* stiffness) const;
  struct MidpointTarget;  // what the cell's fit aims at a midpoint (cursor_midpoints.cc)
  void fit_cell();
  void midpoint_target(int k, MidpointTarget* out) const;
  // `slot`: the cell's refined data (refined_cell()), -1 if none.
  void fit_cell_lattice(const MidpointTarget* targets, std::int32_t slot);
  std::int32_t refined_cell() const;
  void fit_refined_cell(std::int32_t slot);
  bool refined_target(const int (&p)[3], double step, const double* data, double* out) const;
  void fit_refined_trilinear(std::int32_t slot);
  std::int32_t deep_slot(int column, std::int32_t count) const;
  void fit_deep();
  template <int N>
  void deep_point(DeepCell<N>& D, int i, int j, int k, int stage);
  template <int N>
  void deep_base(DeepCell<N>& D, int i, int j, int k);
  template <int N>
  void deep_trilinear_point(DeepCell<N>& D, int i, int j, int k);
  template <int N>
  void deep_cell_at(DeepCell<N>& D, const std::array<double, 3>& s, std::array<double, 3>* value,
                    std::array<double, 9>* slope);
  template <int N>
  void deep_trilinear_cell_at(DeepCell<N>& D, const std::array<double, 3>& s,
                              std::array<double, 3>* value, std::array<double, 9>* k);
  const CellCoefficients& eighth_coefficients(int sub);
  bool sixteenth_here(const std::array<double, 3>& s);
  void eighth_at(const std::array<double, 3>& s, std::array<double, 3>* value,
                 std::array<double, 9>* slope);
  std::array<double, 3> shown_position(const std::array<double, 3>& s,
                                       const std::array<double, 3>& value) const;
  void eighth_trilinear_at(const std::array<double, 3>& s, std::array<double, 3>* value,
                           std::array<double, 9>* k);
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
  // The corners' depth models: force per unit depth at the onset, and its change per unit depth.
  std::array<std::array<double, 3>, 8> per_depth_{}, per_depth_squared_{};
  // In a refined cell near the onset: the depth models at its 125 quarter-spacing lattice points
  // (a, then b; point 25 i + 5 j + k), from the refined points' own force and stiffness where the
  // sphere touches there (fit_local_depth_models); depth_model_at interpolates them then.
  bool local_models_ = false;
  std::array<std::array<double, 6>, 125> local_model_{};
  void fit_local_depth_models(std::int32_t slot);
  // The current cell's rest triangles (indices into section 26; first == end: none).
  std::int32_t surface_first_ = 0, surface_end_ = 0;
  // The force and stiffness of corner c as interpolated: the secant model's in a cell near the
  // onset (onset_), else the stored ones.
  const double* force_of(int c) const {
    return onset_ && corners_[c].secant ? corners_[c].onset->force : corners_[c].force.data();
  }
  const double* stiffness_of(int c) const {
    return onset_ && corners_[c].secant ? corners_[c].onset->stiffness
                                        : corners_[c].stiffness.data();
  }
  std::array<double, 3> last_q_{};  // last probe position, grid units, clamped to the grid
  std::uint64_t calls_ = 0;
  std::uint64_t cells_walked_ = 0;

  Snapshot slots_[3];  // triple buffer: back (writer), middle, front (reader)
  std::uint64_t slot_blend_generation_[3] = {};
  std::uint32_t back_ = 0;
  mutable std::uint32_t front_ = 2;
  mutable std::atomic<std::uint32_t> middle_{1};  // slot index | kFresh
};

}  // namespace hapstate::playback
