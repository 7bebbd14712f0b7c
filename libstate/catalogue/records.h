// Plain rows of the catalogue tables (schema/0001_initial.sql, docs/storage.md). Units:
// lengths in mesh units, forces in N, stiffness in N per mesh unit, times in ms.
#pragma once

#include "blobs/segment.h"
#include "catalogue/direction.h"
#include "catalogue/ids.h"
#include "util/hash.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hapstate {

// Table scene: the scene this state directory belongs to (one row).
struct SceneRecord {
  std::string text;       // scene.toml as read
  ContentHash hash;       // of text
  std::string mesh_file;  // as named in the scene
  ContentHash mesh_hash;  // of the mesh file's bytes
  std::int64_t mesh_nodes = 0;
  std::int64_t mesh_elements = 0;
  std::int64_t mesh_surface_triangles = 0;
  std::array<double, 3> bbox_min{};  // mesh units
  std::array<double, 3> bbox_max{};
  double volume = 0.0;  // mesh units^3

  bool operator==(const SceneRecord&) const = default;
};

// How a stage run ended. kRunning: begun and not finished (or the process died).
enum class StageOutcome { kRunning, kOk, kUnchanged, kPartial, kFailed };
// Its name: the stage_run table's outcome column and inspect's "outcome" key.
const char* stage_outcome_name(StageOutcome outcome);

using Clock = std::chrono::system_clock;
using TimeMs = std::chrono::time_point<Clock, std::chrono::milliseconds>;

// Table stage_run (+ stage_run_input): one execution of a stage and what it consumed.
struct StageRun {
  StageRunId id;      // assigned by the catalogue
  std::string stage;  // "import", "grid", "expand", "compact", "index"
  std::vector<std::pair<std::string, ContentHash>> inputs;  // name -> hash, sorted by name
  std::string parameters;                                   // resolved options as text
  std::string hapstate_version;                             // filled in by the catalogue if ""
  TimeMs started{};
  std::optional<TimeMs> ended;  // nullopt while running
  StageOutcome outcome = StageOutcome::kRunning;
  std::string message;  // summary or failure reason

  bool operator==(const StageRun&) const = default;
};

// Classification of a check-point by the grid stage.
enum class CheckpointClass {
  kUnclassified = 0,
  kWorkspace = 1,         // inside the workspace: configurations are computed here
  kOutsideWorkspace = 2,  // in the grid box but outside the workspace: never expanded into
  kFree = 3,              // contact probe: the sphere does not touch the body (zero config)
  kInsideBody = 4,        // contact probe: the sphere centre is inside the body (unreachable)
};

// Table checkpoint: P_ijk = origin + (i, j, k) * spacing.
struct Checkpoint {
  CheckpointId id;  // kInvalid on insert: assigned by the catalogue
  std::array<int, 3> ijk{};
  std::array<double, 3> position{};  // mesh units
  CheckpointClass classification = CheckpointClass::kUnclassified;

  bool operator==(const Checkpoint&) const = default;
};

// Expansion status of a configuration.
enum class ConfigStatus {
  kOpen = 0,      // some of its 26 directions are undecided (or it is not expandable)
  kExpanded = 1,  // all 26 transitions are stored
  kMerged = 2,    // duplicate level merged into another by compaction; not used any more
};

// The vectors of a blob group (docs/storage.md, "Blob segments"): u (displacements), t (probe
// displacement), h (reactions), du_dp (displacement slopes), and for contact probes touched
// (sticking) or multipliers (frictionless). A configuration's group holds the first four and
// its probe's contact vector; a transition's midpoint group holds u and du_dp.
enum class BlobVector { kU, kT, kH, kDuDp, kTouched, kMultipliers };

// Where a configuration's (or a transition midpoint's) vectors live: blobs/seg-NNNNNN.h5, group
// `name`, one dataset per vector, `name`/u and so on. The one definition of those names.
struct BlobRef {
  SegmentId segment;
  std::string name;  // e.g. "c42"

  bool valid() const { return segment.valid() && !name.empty(); }
  bool operator==(const BlobRef&) const = default;
  // The dataset of vector v in this group: "<name>/u", ...
  std::string dataset(BlobVector v) const { return name + "/" + leaf(v); }
  static const char* leaf(BlobVector v);  // "u", "t", "h", "du_dp", "touched", "multipliers"
  // The group names: configuration `config` ("c42"), and the midpoint of the transition from
  // configuration `source` in direction index `direction` ("m42_13").
  static std::string configuration_group(std::int64_t config);
  static std::string midpoint_group(std::int64_t source, int direction);
  // Whether `group` is a name the two above make ("c<digits>", "m<digits>_<digits>"): a state's
  // vectors, as opposed to anything else a segment may hold.
  static bool is_state_group(std::string_view group);
};

// Table configuration: one equilibrium state (a level of a check-point).
struct Configuration {
  ConfigId id;  // kInvalid on insert: assigned (or give one to fix it)
  CheckpointId checkpoint;
  Level level;
  int wave = 0;                       // breadth-first distance from a zero configuration
  std::array<double, 3> force{};      // felt by the user, N
  std::array<double, 9> stiffness{};  // d(force)/d(probe), row-major, N per mesh unit
  bool expandable = false;            // |force| <= F_max and inside the workspace
  ConfigStatus status = ConfigStatus::kOpen;
  std::optional<BlobRef> blob;  // nullopt: no vectors stored (e.g. the trivial zero state)
  std::vector<double> summary;  // small sketch for fast level comparison

  bool operator==(const Configuration&) const = default;
};

// Result of a transition.
enum class TransitionOutcome {
  kReached = 0,      // target is the configuration reached
  kOutsideGrid = 1,  // the neighbour is not a check-point of the grid / workspace
  kFailed = 2,       // the solve failed; failure_reason says why
};

// Table transition: moving the probe from `source` one grid step in `direction`.
struct Transition {
  ConfigId source;
  Direction direction{0};
  TransitionOutcome outcome = TransitionOutcome::kReached;
  ConfigId target;  // valid iff outcome == kReached
  int substeps = 0;
  int newton_iterations = 0;
  int factorisations = 0;       // numeric factorisations spent (schema 2; 0 in older rows)
  double final_residual = 0.0;  // N
  double wall_ms = 0.0;
  std::string failure_reason;  // "" unless kFailed
  // The force felt half-way through the move, N (schema 3): solved for the directions whose
  // offsets are all >= 0 when the move reached its target; none otherwise.
  std::optional<std::array<double, 3>> midpoint_force;
  // The haptic stiffness there, row-major, N per mesh unit (schema 4): with the midpoint force,
  // when it was computable; none in older rows.
  std::optional<std::array<double, 9>> midpoint_stiffness;
  // The displacements and their slopes d u / d p there (schema 5): blobs/seg-NNNNNN.h5, group
  // `name` ("m<source>_<direction>") holding `name`/u (float32, mesh units) and `name`/du_dp
  // (float32, 3 columns); with the midpoint force, none in older rows.
  std::optional<BlobRef> midpoint_blob;

  bool operator==(const Transition&) const = default;
};

// Table refinement (schema 6): one solved point of a refined cell's quarter-spacing lattice, of
// its eighth-spacing one (refinement depth 2) or of its sixteenth-spacing one (depth 3).
// RefinementPoint::point: the first index of each depth's lattice, and the last index.
inline constexpr int kEighthFirstPoint = 125, kSixteenthFirstPoint = 854,
                     kLastRefinementPoint = 5766;
// The refinement depth (1, 2 or 3) a RefinementPoint::point belongs to.
constexpr int refinement_point_depth(int point) {
  return point < kEighthFirstPoint ? 1 : point < kSixteenthFirstPoint ? 2 : 3;
}

struct RefinementPoint {
  ConfigId cell;  // the configuration at the cell's lowest corner
  // 25 i + 5 j + k for quarter steps (i, j, k) from that corner (0..124); 125 + 81 i + 9 j + k for
  // eighth steps (125..853, at least one of them odd); 854 + 289 i + 17 j + k for sixteenth steps
  // (854..5766, at least one of them odd; depth 3, only in the eighth cells the stage flagged).
  int point = 0;
  bool reached = false;
  std::array<double, 3> force{};      // felt by the user, N (when reached)
  std::array<double, 9> stiffness{};  // row-major, N per mesh unit (when reached)
  int newton_iterations = 0;
  double wall_ms = 0.0;
  std::string failure_reason;  // "" when reached

  bool operator==(const RefinementPoint&) const = default;
};

// Table certificate_path and its certificate_step rows: one seeded random path of the
// certificate (docs/certificate.md), measured on the playback file of `playback_hash`.
struct CertificateStep {
  int step = 0;                     // 1..steps
  std::array<double, 3> probe{};    // mesh units
  std::array<int, 3> cell{};        // grid index of the cell's lowest corner
  std::array<int, 3> checkpoint{};  // grid index of the nearest check-point
  double force = 0.0;               // |f*|, N
  bool solved = false;
  bool onset = false;                   // contact onset (out of the deformation statistics)
  std::array<double, 2> error{};        // |f - f*| in N: trilinear, Hermite
  std::array<double, 2> deformation{};  // ||u - u*|| / ||u*||, surface: trilinear, Hermite

  bool operator==(const CertificateStep&) const = default;
};

struct CertificatePath {
  int seed = 0;
  ContentHash playback_hash;
  int steps = 0;
  double max_force = 0.0;  // N
  int failures = 0;
  double wall_ms = 0.0;
  std::vector<CertificateStep> rows;  // by step

  bool operator==(const CertificatePath&) const = default;
};

// What one two-sided solve found (eval/equilibria.h).
enum class Equilibria {
  kOne,        // both approaches agree
  kTwo,        // they disagree: the force jumps near here
  kEnds,       // Newton failed on one approach only: likely an equilibrium ending near here
  kUndecided,  // an approach did not reach its start, or neither converged
};
// Its name: the certificate_equilibria table's verdict column, inspect's "verdict" key and
// Python's: "one", "two", "ends", "undecided".
const char* equilibria_name(Equilibria e);

// Table certificate_equilibria: the two-sided solve at one of the certificate's worst steps
// along one axis (eval/equilibria.h; docs/certificate.md, "When it is not good enough").
struct CertificateEquilibria {
  int seed = 0, step = 0;
  int axis = 0;      // 0, 1, 2: the approach is along x, y, z
  double along = 0;  // mesh units: from the position - along and + along on that axis
  Equilibria verdict = Equilibria::kUndecided;
  std::optional<std::array<double, 3>> force_minus, force_plus;  // N; none: Newton failed
  ContentHash playback_hash;
  double wall_ms = 0.0;

  bool operator==(const CertificateEquilibria&) const = default;
};

// Table certificate (one row): what a complete certify run measured besides the paths.
struct CertificateRun {
  ContentHash playback_hash;
  int paths = 0;
  int steps = 0;
  std::int64_t queries = 0;
  double query_median_ns = 0.0;
  double query_p999_ns = 0.0;
  double stiffness = 0.0;  // N/m, the largest |eigenvalue| of a stored stiffness
  TimeMs ended{};

  bool operator==(const CertificateRun&) const = default;
};

}  // namespace hapstate
