// Opening a catalogue: validation before any write, migrations, connection settings.
#include "catalogue/catalogue.h"

#include "catalogue/catalogue_impl.hpp"
#include "catalogue/schema.hpp"
#include "util/error.h"

#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace hapstate {

using catalogue_detail::Database;

namespace {

std::string hex32(std::int64_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", static_cast<unsigned>(static_cast<std::uint32_t>(v)));
  return text;
}

// A non-empty file must start with the SQLite magic; checked before SQLite sees the file so
// the message is precise and nothing is touched.
void check_sqlite_header(const std::filesystem::path& file, const std::string& label) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw InputError(label + ": cannot read the catalogue: " + ec.message());
  if (size == 0) return;                                 // an empty file is an empty database
  static constexpr char kMagic[16] = "SQLite format 3";  // 15 characters and '\0'
  char head[16] = {};
  std::ifstream in(file, std::ios::binary);
  in.read(head, sizeof head);
  if (size < 100 || in.gcount() != 16 || std::memcmp(head, kMagic, 16) != 0) {
    throw InputError(label + ": not an SQLite database (" + std::to_string(size) +
                     " bytes without the SQLite header): not a hapstate catalogue");
  }
}

struct SchemaState {
  std::int64_t application_id = 0;
  std::int64_t version = 0;
  std::int64_t objects = 0;  // rows of sqlite_schema
  bool empty() const { return application_id == 0 && version == 0 && objects == 0; }
};

SchemaState read_schema_state(Database& db) {
  SchemaState s;
  s.application_id = db.query_int("PRAGMA application_id");
  s.version = db.query_int("PRAGMA user_version");
  s.objects = db.query_int("SELECT count(*) FROM sqlite_schema");
  return s;
}

// Throws unless a catalogue in state `s` may be opened with `mode`.
void check_schema_state(const SchemaState& s, OpenMode mode, const std::string& label) {
  const int supported = Catalogue::supported_schema_version();
  if (s.empty()) {
    if (mode == OpenMode::kReadOnly || mode == OpenMode::kReadWrite) {
      throw InputError(label + ": empty catalogue (no schema): not created by hapstate");
    }
    return;
  }
  if (s.application_id != Catalogue::kApplicationId) {
    throw InputError(label + ": not a hapstate catalogue (SQLite application_id " +
                     hex32(s.application_id) + ", expected " + hex32(Catalogue::kApplicationId) +
                     ")");
  }
  if (s.version > supported) {
    throw InputError(label + " has schema version " + std::to_string(s.version) +
                     ", this hapstate supports up to " + std::to_string(supported) +
                     ": upgrade hapstate");
  }
  if (s.version < supported && mode != OpenMode::kMigrate) {
    throw InputError(
        label + " has schema version " + std::to_string(s.version) + ", this hapstate needs " +
        std::to_string(supported) +
        ": run any writing stage on it (hapstate-expand, -compact, -index, or hapstate run) "
        "and it is migrated");
  }
  if (s.version < 1)
    throw InputError(label + ": invalid schema version " + std::to_string(s.version));
}

// Applies every migration above the current version, each in its own transaction.
void migrate(Database& db) {
  for (const auto& m : catalogue_detail::embedded_migrations()) {
    db.exec("BEGIN IMMEDIATE");
    try {
      if (db.query_int("PRAGMA user_version") >= m.version) {  // another process was first
        db.exec("ROLLBACK");
        continue;
      }
      db.exec(m.sql);
      db.exec("PRAGMA user_version = " + std::to_string(m.version));
      db.exec("PRAGMA application_id = " + std::to_string(Catalogue::kApplicationId));
      db.exec("COMMIT");
    } catch (const InputError& e) {
      sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw InputError(std::string(e.what()) + " [migration schema/" + m.file_name + "]");
    } catch (const EnvironmentError& e) {
      sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw EnvironmentError(std::string(e.what()) + " [migration schema/" + m.file_name + "]");
    }
  }
}

}  // namespace

int Catalogue::supported_schema_version() {
  const auto migrations = catalogue_detail::embedded_migrations();
  return migrations.empty() ? 0 : migrations.back().version;
}

Catalogue::Catalogue(const std::filesystem::path& file, OpenMode mode)
    : impl_(std::make_unique<Impl>()) {
  impl_->file = file;
  const bool memory = file == ":memory:";
  const bool may_create = mode == OpenMode::kCreate || mode == OpenMode::kMigrate;
  const std::string label = file.string();

  if (!memory) {
    std::error_code ec;
    const bool exists = std::filesystem::exists(file, ec);
    if (!exists && !may_create) {
      throw InputError(label + ": no catalogue here (the import stage creates it)");
    }
    if (exists) {
      // Validate through a read-only connection first: a refused file is never written to.
      check_sqlite_header(file, label);
      Database probe(file.string(), SQLITE_OPEN_READONLY, label);
      // As the connection below: a writer's commit or a recovery of the WAL after a crash may
      // hold a lock for a moment.
      sqlite3_busy_timeout(probe.get(), kBusyTimeoutMs);
      check_schema_state(read_schema_state(probe), mode, label);
    }
  }

  int flags = mode == OpenMode::kReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  if (may_create) flags |= SQLITE_OPEN_CREATE;
  impl_->db = std::make_unique<Database>(file.string(), flags, label);
  Database& db = *impl_->db;
  sqlite3_busy_timeout(db.get(), kBusyTimeoutMs);
  if (mode != OpenMode::kReadOnly) {
    const std::string journal = db.query_text("PRAGMA journal_mode = WAL");
    if (journal != "wal" && !(memory && journal == "memory")) {
      throw InputError(label + ": cannot switch the catalogue to WAL mode (journal_mode " +
                       journal + ")");
    }
    db.exec("PRAGMA synchronous = NORMAL");
  }
  db.exec("PRAGMA foreign_keys = ON");

  const SchemaState state = read_schema_state(db);
  check_schema_state(state, mode, label);  // again: another process may have changed it
  if (mode != OpenMode::kReadOnly) migrate(db);
  impl_->schema_version = static_cast<int>(db.query_int("PRAGMA user_version"));
  if (impl_->schema_version != supported_schema_version()) {
    throw InputError(label + ": schema version " + std::to_string(impl_->schema_version) +
                     " after opening, expected " + std::to_string(supported_schema_version()));
  }
}

Catalogue::~Catalogue() = default;
Catalogue::Catalogue(Catalogue&&) noexcept = default;
Catalogue& Catalogue::operator=(Catalogue&&) noexcept = default;

const std::filesystem::path& Catalogue::file() const { return impl_->file; }

int Catalogue::schema_version() const { return impl_->schema_version; }

std::string Catalogue::integrity_check() { return impl_->db->query_text("PRAGMA integrity_check"); }

std::int64_t Catalogue::num_foreign_key_violations() {
  catalogue_detail::Statement s(*impl_->db, "PRAGMA foreign_key_check");
  std::int64_t n = 0;
  while (s.step()) ++n;
  return n;
}

namespace catalogue_detail {

int ranged_column(const Statement& s, int column, int lo, int hi, const std::string& label,
                  const char* name) {
  const std::int64_t v = s.column_int(column);
  if (v < lo || v > hi)
    throw InputError(label + ": damaged catalogue: " + name + " = " + std::to_string(v) +
                     ", not in " + std::to_string(lo) + ".." + std::to_string(hi));
  return static_cast<int>(v);
}

std::vector<std::byte> pack_doubles(std::span<const double> values) {
  std::vector<std::byte> bytes(values.size() * 8);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto bits = std::bit_cast<std::uint64_t>(values[i]);
    for (int b = 0; b < 8; ++b) bytes[8 * i + b] = static_cast<std::byte>(bits >> (8 * b));
  }
  return bytes;
}

std::vector<double> unpack_doubles(std::span<const std::byte> bytes, const std::string& where) {
  if (bytes.size() % 8 != 0) {
    throw InputError(where + ": float64 array of " + std::to_string(bytes.size()) +
                     " bytes (not a multiple of 8)");
  }
  std::vector<double> values(bytes.size() / 8);
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint64_t bits = 0;
    for (int b = 7; b >= 0; --b)
      bits = (bits << 8) | std::to_integer<std::uint64_t>(bytes[8 * i + b]);
    values[i] = std::bit_cast<double>(bits);
  }
  return values;
}

}  // namespace catalogue_detail
}  // namespace hapstate
