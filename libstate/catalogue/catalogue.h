// The catalogue of a state directory: catalogue.sqlite, all metadata and every decision of the
// precomputation (docs/storage.md). A narrow interface with one verb grammar per table:
//   insert_<row>, read_<row>(id), read_all_<rows>, num_<rows>, exists_<row>, update_<row>_<field>,
// plus the few queries the stages need (configurations_at, frontier, transitions_of, ...).
#pragma once

#include "catalogue/query.h"
#include "catalogue/records.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace hapstate {

enum class OpenMode {
  kReadOnly,   // must exist at the current schema version; no writes
  kReadWrite,  // must exist at the current schema version
  kCreate,     // created with the current schema if missing (or empty); else as kReadWrite
  kMigrate,    // like kCreate, and an older schema is migrated to the current one
};

// One open connection to a catalogue file (or ":memory:").
// Threads: a Catalogue is used by one thread at a time; every thread that needs the catalogue
// opens its own (SQLite WAL allows many readers beside one writer; a writer waits up to
// kBusyTimeoutMs for another's transaction). Errors: every failure names the file, the SQL
// statement and SQLite's message; an environment failure (disk full, I/O error, permission,
// locked) throws EnvironmentError, anything else InputError; nothing is written when opening
// fails.
class Catalogue {
 public:
  // "HAPS": PRAGMA application_id of every hapstate catalogue.
  static constexpr std::int32_t kApplicationId = 0x48415053;
  static constexpr int kBusyTimeoutMs = 10000;

  // Schema version this build creates and reads (the highest schema/NNNN_*.sql).
  static int supported_schema_version();

  // Opens `file`. Refused with an InputError, leaving the file untouched: not an SQLite file,
  // a corrupt file, an SQLite file of another application, a newer schema version ("upgrade
  // hapstate"), an older one unless kMigrate, a missing file unless kCreate / kMigrate.
  // Sets WAL, synchronous=NORMAL and foreign keys on.
  explicit Catalogue(const std::filesystem::path& file, OpenMode mode = OpenMode::kReadWrite);
  ~Catalogue();
  Catalogue(Catalogue&&) noexcept;
  Catalogue& operator=(Catalogue&&) noexcept;

  const std::filesystem::path& file() const;
  int schema_version() const;
  // PRAGMA integrity_check: "ok" or SQLite's list of problems.
  std::string integrity_check();
  // PRAGMA foreign_key_check: number of rows whose references dangle.
  std::int64_t num_foreign_key_violations();

  // --- scene (one row) ---
  // Inserts or replaces the scene row.
  void write_scene(const SceneRecord& scene);
  std::optional<SceneRecord> read_scene();

  // --- stage runs ---
  // Inserts a run (with its inputs) as given; fills in hapstate_version if empty. Returns its id.
  StageRunId insert_stage_run(const StageRun& run);
  // Sets outcome, end time and message of a run (typically one inserted as kRunning).
  void update_stage_run_end(StageRunId id, StageOutcome outcome, TimeMs ended,
                            std::string_view message);
  StageRun read_stage_run(StageRunId id);
  std::vector<StageRun> read_stage_runs(std::string_view stage);  // oldest first
  // The newest run of `stage` that ended kOk or kUnchanged, if any: the one to compare
  // input hashes against.
  std::optional<StageRun> last_successful_stage_run(std::string_view stage);

  // --- check-points ---
  // Inserts a check-point; its id is assigned unless checkpoint.id is valid. Throws if the
  // (i, j, k) already exists.
  CheckpointId insert_checkpoint(const Checkpoint& checkpoint);
  Checkpoint read_checkpoint(CheckpointId id);  // throws InputError if there is no such row
  std::optional<Checkpoint> find_checkpoint(const std::array<int, 3>& ijk);
  std::vector<Checkpoint> read_all_checkpoints();  // by id
  std::int64_t num_checkpoints();
  bool exists_checkpoint(CheckpointId id);

  // --- configurations ---
  // Inserts a configuration; its id is assigned unless configuration.id is valid (a stage
  // that names blob groups after ids before the insert fixes them this way). Throws if
  // (checkpoint, level) exists or the check-point does not.
  ConfigId insert_configuration(const Configuration& configuration);
  Configuration read_configuration(ConfigId id);  // throws InputError if there is no such row
  std::vector<Configuration> configurations_at(CheckpointId checkpoint);  // by level
  // Expandable, kOpen configurations of `wave`, by id: the work list of the expand stage.
  std::vector<Configuration> frontier(int wave);
  std::vector<Configuration> read_all_configurations();  // by id
  std::int64_t num_configurations();
  bool exists_configuration(ConfigId id);
  void update_configuration_status(ConfigId id, ConfigStatus status);
  // Sets the expandable flag (e.g. after the device limit F_max changed). Throws InputError if
  // there is no such configuration.
  void update_configuration_expandable(ConfigId id, bool expandable);
  std::optional<int> max_wave();  // nullopt if there is no configuration
  // Next level number at a check-point (0 if it has none).
  Level next_level(CheckpointId checkpoint);
  // Largest configuration id in use (kInvalid if none): ids above it are free.
  ConfigId max_config_id();
  // Every segment some configuration or transition (its midpoint vectors) references: the
  // complement is garbage.
  std::set<SegmentId> referenced_segments();

  // --- transitions ---
  // Inserts a transition. Throws if (source, direction) exists, if target and outcome
  // disagree, or if source / target are not configurations.
  void insert_transition(const Transition& transition);
  std::optional<Transition> read_transition(ConfigId source, Direction direction);
  std::vector<Transition> transitions_of(ConfigId source);  // by direction
  std::vector<Transition> read_all_transitions();           // by (source, direction)
  std::int64_t num_transitions();
  std::int64_t num_failed_transitions();
  // Deletes the decision (source, direction), e.g. an kOutsideGrid outcome whose neighbour
  // became part of an enlarged workspace. Returns whether a row was deleted.
  bool delete_transition(ConfigId source, Direction direction);

  // --- refinement (refinement_table.cc) ---
  // Inserts the points of one cell (all in one savepoint). Throws if a (cell, point) exists.
  void insert_refinement_points(const std::vector<RefinementPoint>& points);
  std::vector<RefinementPoint> read_all_refinement_points();  // by (cell, point)
  // The cells with rows at depth 1 (quarter-spacing points), 2 (eighth-spacing) or 3 (sixteenth).
  std::set<ConfigId> refined_cells(int depth = 1);
  std::int64_t num_refinement_points();

  // --- certificate (hapstate-certify; certificate_table.cc) ---
  // Inserts a path with its steps (one savepoint). Throws if the seed exists.
  void insert_certificate_path(const CertificatePath& path);
  std::vector<CertificatePath> read_all_certificate_paths();  // by seed, with their steps
  // Deletes the paths measured on something other than `playback_hash` (a playback file and the
  // playback code, hashed together: certified_hash in maintenance/), with another
  // number of steps, or with a seed above `paths`, and the certificate row unless it is of the
  // same file, step count and number of paths. Returns the paths deleted.
  std::int64_t delete_stale_certificate(const ContentHash& playback_hash, int steps, int paths);
  // The two-sided solves at worst steps: inserted a step at a time (its axes in one savepoint;
  // throws if a (seed, step, axis) exists), read by (seed, step, axis). delete_stale_certificate
  // deletes those of another playback file or of a path it deletes.
  void insert_certificate_equilibria(const std::vector<CertificateEquilibria>& rows);
  std::vector<CertificateEquilibria> read_all_certificate_equilibria();
  void write_certificate(const CertificateRun& run);  // inserts or replaces the one row
  void delete_certificate();                          // the one row, if any (not the paths)
  std::optional<CertificateRun> read_certificate();

  // --- maintenance (hapstate-compact; maintenance_verbs.cc) ---
  // Points configuration `id` at `blob` (nullopt: no vectors stored). Throws InputError if
  // there is no such configuration.
  void update_configuration_blob(ConfigId id, const std::optional<BlobRef>& blob);
  // Points the midpoint vectors of transition (source, direction) at `blob`. Returns whether
  // the row exists (a row deleted by a level merge is not an error).
  bool update_transition_midpoint_blob(ConfigId source, Direction direction, const BlobRef& blob);
  // Every transition whose target is `from` targets `to` instead. Returns the rows changed.
  std::int64_t retarget_transitions(ConfigId from, ConfigId to);
  // Gives the transitions of `from` to source `to` in every direction `to` has not decided
  // yet; the others stay with `from`. Returns the rows moved.
  std::int64_t move_transitions(ConfigId from, ConfigId to);
  // VACUUM (rewrites the file without free pages) and PRAGMA wal_checkpoint(TRUNCATE) (empties
  // the WAL). Not inside a Transaction; needs no other connection reading at the time.
  void vacuum();
  // Runs one read-only SQL statement and returns all its rows (query.cc). Refused with an
  // InputError, before anything runs: more than one statement, a statement that could write
  // (sqlite3_stmt_readonly), ATTACH / DETACH, transaction control, a PRAGMA with a value.
  // On a kReadOnly catalogue SQLite itself refuses writes as well.
  QueryResult query_read_only(std::string_view sql);
  // Whether a Transaction is open on this catalogue.
  bool in_transaction() const;

 private:
  friend class Transaction;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapstate
