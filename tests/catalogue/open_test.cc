// Opening catalogues: creation settings, refusal of foreign, future, corrupt and missing
// files without touching them, read-only access, several connections.
#include "../blobs/temp_dir.h"
#include "catalogue/catalogue.h"
#include "catalogue/sqlite.hpp"
#include "catalogue/transaction.h"
#include "util/error.h"

#include "../common/expect_input_error.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <iterator>
#include <string>

namespace hapstate {
namespace {

using test_util::TempDir;

using test_util::expect_input_error;

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs SQL on a file with plain SQLite, outside the library; returns the first column of the
// last row as text.
std::string raw_sql(const std::filesystem::path& file, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
  std::string result;
  char* error = nullptr;
  auto keep = [](void* out, int n, char** values, char**) {
    if (n > 0 && values[0] != nullptr) *static_cast<std::string*>(out) = values[0];
    return 0;
  };
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), keep, &result, &error), SQLITE_OK)
      << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
  return result;
}

void fill(Catalogue& cat) {
  Checkpoint c;
  c.ijk = {1, 2, 3};
  c.classification = CheckpointClass::kWorkspace;
  const CheckpointId id = cat.insert_checkpoint(c);
  Configuration config;
  config.checkpoint = id;
  config.level = Level(0);
  cat.insert_configuration(config);
}

// Expects opening `file` with every mode to fail with `part`, and the file to stay unchanged.
void expect_refused_untouched(const std::filesystem::path& file, const std::string& part) {
  const std::string before = file_bytes(file);
  const auto mtime = std::filesystem::last_write_time(file);
  for (OpenMode mode :
       {OpenMode::kReadOnly, OpenMode::kReadWrite, OpenMode::kCreate, OpenMode::kMigrate}) {
    expect_input_error([&] { Catalogue cat(file, mode); }, part);
  }
  EXPECT_EQ(file_bytes(file), before);
  EXPECT_EQ(std::filesystem::last_write_time(file), mtime);
}

// A full disk is not bad input: SQLite's SQLITE_FULL (here from a page limit, the way a full
// disk reports itself) is an EnvironmentError naming the catalogue (exit code 4), not an
// InputError (exit code 2).
TEST(CatalogueOpen, FullDiskIsAnEnvironmentErrorNotBadInput) {
  TempDir dir("catalogue_full");
  const std::string file = (dir.path() / "full.sqlite").string();
  catalogue_detail::Database db(file, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, file);
  db.exec("CREATE TABLE t (x BLOB)");
  db.exec("PRAGMA max_page_count = 3");
  try {
    for (int k = 0; k < 100; ++k) db.exec("INSERT INTO t VALUES (zeroblob(4000))");
    FAIL() << "the page limit was never reached";
  } catch (const EnvironmentError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find("full"), std::string::npos) << message;
  } catch (const InputError& e) {
    FAIL() << "a full disk reported as bad input: " << e.what();
  }
}

TEST(CatalogueOpen, CreateSetsWalApplicationIdAndVersion) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    fill(cat);
    EXPECT_EQ(cat.file(), file);
  }
  EXPECT_EQ(raw_sql(file, "PRAGMA journal_mode"), "wal");
  EXPECT_EQ(raw_sql(file, "PRAGMA application_id"), std::to_string(0x48415053));
  EXPECT_EQ(raw_sql(file, "PRAGMA user_version"), "10");
  EXPECT_EQ(raw_sql(file, "SELECT count(*) FROM configuration"), "1");
  EXPECT_EQ(raw_sql(file, "SELECT name FROM sqlite_schema WHERE name = 'configuration_frontier'"),
            "configuration_frontier");
}

TEST(CatalogueOpen, ReopenReadWriteAndReadOnly) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    fill(cat);
  }
  {
    Catalogue cat(file, OpenMode::kCreate);  // existing and current: opened as is
    EXPECT_EQ(cat.num_configurations(), 1);
  }
  {
    Catalogue cat(file, OpenMode::kReadWrite);
    EXPECT_EQ(cat.num_checkpoints(), 1);
  }
  Catalogue reader(file, OpenMode::kReadOnly);
  EXPECT_EQ(reader.num_configurations(), 1);
  Checkpoint c;
  c.ijk = {9, 9, 9};
  // SQLite's READONLY (a read-only file, here a read-only connection) is no bad input.
  EXPECT_THROW(reader.insert_checkpoint(c), EnvironmentError);
}

TEST(CatalogueOpen, MissingFileIsNotCreatedUnlessAsked) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadWrite); }, "no catalogue here");
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadOnly); }, "no catalogue here");
  EXPECT_FALSE(std::filesystem::exists(file));
  Catalogue cat(file, OpenMode::kMigrate);  // migration from nothing
  EXPECT_EQ(cat.schema_version(), 10);
}

TEST(CatalogueOpen, EmptyFileIsMigratedFromScratch) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  std::ofstream(file).close();
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadWrite); }, "empty catalogue");
  Catalogue cat(file, OpenMode::kCreate);
  EXPECT_EQ(cat.schema_version(), 10);
  EXPECT_EQ(cat.integrity_check(), "ok");
}

TEST(CatalogueOpen, FutureSchemaVersionIsRefusedAndFileUnchanged) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    fill(cat);
  }
  raw_sql(file, "PRAGMA user_version = 11");
  ASSERT_FALSE(std::filesystem::exists(file.string() + "-wal"));  // checkpointed on close
  expect_refused_untouched(
      file,
      file.string() + " has schema version 11, this hapstate supports up to 10: upgrade hapstate");
}

TEST(CatalogueOpen, OlderSchemaVersionNeedsExplicitMigration) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  raw_sql(file, "CREATE TABLE t (x); PRAGMA application_id = " +
                    std::to_string(Catalogue::kApplicationId));
  const std::string before = file_bytes(file);
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadWrite); },
                     "has schema version 0, this hapstate needs 10: run any writing stage on it");
  expect_input_error([&] { Catalogue cat(file, OpenMode::kCreate); },
                     "run any writing stage on it");
  EXPECT_EQ(file_bytes(file), before);
}

TEST(CatalogueOpen, NonSqliteFileIsRefusedUntouched) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  std::ofstream(file) << std::string(500, '#') << " this is a scene file, not a database\n";
  expect_refused_untouched(file, "not an SQLite database");
  std::ofstream(file, std::ios::trunc) << "short";
  expect_refused_untouched(file, "not an SQLite database");
}

TEST(CatalogueOpen, OtherApplicationsDatabaseIsRefused) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  raw_sql(file, "CREATE TABLE photos (id INTEGER PRIMARY KEY, name TEXT)");
  expect_refused_untouched(file, "not a hapstate catalogue (SQLite application_id 0x00000000");
}

TEST(CatalogueOpen, CorruptFileGivesAClearError) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    fill(cat);
  }
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    const std::string junk(3000, '\xAB');  // page 1 after the header: the schema table
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadWrite); },
                     "the catalogue file is corrupt or not an SQLite database");
}

// Values outside the schema's CHECKed ranges in a damaged file (found by fuzz/catalogue_fuzz:
// a transition direction of 31 threw std::out_of_range, an internal error) are bad input that
// names the catalogue, the column and the value.
TEST(CatalogueOpen, OutOfRangeValuesInADamagedFileAreInputErrors) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    fill(cat);
    Transition t;
    t.source = cat.read_all_configurations().front().id;
    t.direction = Direction(3);
    t.outcome = TransitionOutcome::kOutsideGrid;
    cat.insert_transition(t);
  }
  const std::string damage = "PRAGMA ignore_check_constraints = ON; ";
  raw_sql(file, damage + "UPDATE transition SET direction = 31");
  {
    Catalogue cat(file, OpenMode::kReadOnly);
    expect_input_error([&] { cat.read_all_transitions(); },
                       "damaged catalogue: transition.direction = 31, not in 0..25");
  }
  raw_sql(file, damage + "UPDATE transition SET direction = 3, outcome = 7");
  raw_sql(file, damage + "UPDATE checkpoint SET classification = 9");
  raw_sql(file, damage + "UPDATE configuration SET status = -1");
  Catalogue cat(file, OpenMode::kReadOnly);
  expect_input_error([&] { cat.read_all_transitions(); }, "transition.outcome = 7, not in 0..2");
  expect_input_error([&] { cat.read_all_checkpoints(); },
                     "checkpoint.classification = 9, not in 0..4");
  expect_input_error([&] { cat.read_all_configurations(); },
                     "configuration.status = -1, not in 0..2");
}

TEST(CatalogueOpen, AnUnknownTwoSidedVerdictIsAnInputError) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  {
    Catalogue cat(file, OpenMode::kCreate);
    CertificateEquilibria e;
    e.seed = 1;
    e.step = 1;
    e.along = 0.01;
    e.verdict = Equilibria::kTwo;
    e.playback_hash = ContentHash{0x1234};
    e.wall_ms = 1;
    cat.insert_certificate_equilibria({e});
    ASSERT_EQ(cat.read_all_certificate_equilibria().front().verdict, Equilibria::kTwo);
  }
  raw_sql(file,
          "PRAGMA ignore_check_constraints = ON; "
          "UPDATE certificate_equilibria SET verdict = 'three'");
  Catalogue cat(file, OpenMode::kReadOnly);
  expect_input_error([&] { cat.read_all_certificate_equilibria(); },
                     "damaged catalogue: certificate_equilibria.verdict = 'three'");
}

TEST(CatalogueOpen, SecondConnectionSeesCommittedWrites) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  Catalogue writer(file, OpenMode::kCreate);
  Catalogue reader(file, OpenMode::kReadOnly);
  {
    Transaction tx(writer);
    fill(writer);
    EXPECT_EQ(reader.num_configurations(), 0);  // not committed yet
    tx.commit();
  }
  EXPECT_EQ(reader.num_configurations(), 1);
  Catalogue second_writer(file, OpenMode::kReadWrite);
  Transaction tx(writer);
  Checkpoint c;
  c.ijk = {5, 5, 5};
  writer.insert_checkpoint(c);
  tx.commit();
  EXPECT_EQ(second_writer.num_checkpoints(), 2);
  EXPECT_EQ(second_writer.integrity_check(), "ok");
}

}  // namespace
}  // namespace hapstate

namespace hapstate {
namespace {

// A catalogue of schema 1 (written with schema/0001_initial.sql alone, as hapstate 0.1 did) is
// migrated by a writing open: the transition table gains `factorisations` (old rows count 0)
// and the midpoint force, stiffness and displacement blob (old rows have none); a new row keeps
// them.
TEST(CatalogueOpen, SchemaOneIsMigratedAndOldTransitionsCountNoFactorisations) {
  TempDir dir("open");
  const auto file = dir.path() / "catalogue.sqlite";
  std::ifstream in(HAPSTATE_SOURCE_DIR "/schema/0001_initial.sql");
  const std::string schema_one(std::istreambuf_iterator<char>(in), {});
  raw_sql(file, schema_one + "; PRAGMA user_version = 1; PRAGMA application_id = " +
                    std::to_string(Catalogue::kApplicationId));
  raw_sql(
      file,
      "INSERT INTO checkpoint (i, j, k, x, y, z, classification) VALUES (0, 0, 0, 0, 0, 0, 1);"
      "INSERT INTO configuration (id, checkpoint, level, wave, force_x, force_y, force_z, k_xx, "
      "k_xy, k_xz, k_yx, k_yy, k_yz, k_zx, k_zy, k_zz, expandable, status, summary) "
      "VALUES (1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, x'');"
      "INSERT INTO transition (source, direction, outcome, target, substeps, "
      "newton_iterations, final_residual, wall_ms) VALUES (1, 3, 1, NULL, 0, 0, 0, 0)");
  expect_input_error([&] { Catalogue cat(file, OpenMode::kReadWrite); },
                     "has schema version 1, this hapstate needs 10");
  Catalogue cat(file, OpenMode::kMigrate);
  EXPECT_EQ(cat.schema_version(), 10);
  const auto t = cat.read_transition(ConfigId(1), Direction(3));
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->factorisations, 0);
  EXPECT_FALSE(t->midpoint_force.has_value());
  EXPECT_FALSE(t->midpoint_stiffness.has_value());
  EXPECT_FALSE(t->midpoint_blob.has_value());
  Transition u = *t;
  u.direction = Direction(25);
  u.outcome = TransitionOutcome::kReached;
  u.target = ConfigId(1);
  u.midpoint_force = std::array<double, 3>{0.25, -1.5, 3e-7};
  u.midpoint_stiffness = std::array<double, 9>{-1, 0.5, 0, 0.5, -2, 1e-9, 0, 1e-9, -3};
  u.midpoint_blob = BlobRef{SegmentId{7}, "m1_25"};
  cat.insert_transition(u);
  EXPECT_EQ(cat.read_transition(ConfigId(1), Direction(25)), u);
  EXPECT_EQ(cat.integrity_check(), "ok");
}

}  // namespace
}  // namespace hapstate
