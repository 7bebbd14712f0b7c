#include "catalogue/sqlite.hpp"

#include "util/error.h"

#include <cstring>

namespace hapstate::catalogue_detail {
namespace {

std::string shorten(std::string_view sql) {
  std::string text(sql.substr(0, 240));
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  if (sql.size() > 240) text += " ...";
  return text;
}

// SQLite result codes that say the environment failed, not the catalogue's content.
bool environment_failure(int rc) {
  switch (rc & 0xFF) {
    case SQLITE_FULL:
    case SQLITE_IOERR:
    case SQLITE_CANTOPEN:
    case SQLITE_PERM:
    case SQLITE_READONLY:
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_NOMEM:
    case SQLITE_NOLFS:
    case SQLITE_PROTOCOL:
      return true;
    default:
      return false;
  }
}

// What failed behind an I/O or open failure, in parentheses after SQLite's message: for
// SQLITE_IOERR the operation its extended code names ("disk I/O error (write failed,
// SQLITE_IOERR_WRITE)"; SQLite's record of the OS errno is not reliable then: it reads errno
// when the error reaches the API, after the rollback's own calls), for SQLITE_CANTOPEN the OS
// error of the failed open.
std::string os_error(sqlite3* db, int rc) {
  const int primary = rc & 0xFF;
  if (primary == SQLITE_CANTOPEN && db != nullptr) {
    const int e = sqlite3_system_errno(db);
    return e > 0 ? std::string(" (") + os_error_text(e) + ")" : std::string();
  }
  if (primary != SQLITE_IOERR) return "";
  switch (rc) {
    case SQLITE_IOERR_WRITE:
      return " (write failed, SQLITE_IOERR_WRITE)";
    case SQLITE_IOERR_READ:
      return " (read failed, SQLITE_IOERR_READ)";
    case SQLITE_IOERR_SHORT_READ:
      return " (short read, SQLITE_IOERR_SHORT_READ)";
    case SQLITE_IOERR_FSYNC:
      return " (fsync failed, SQLITE_IOERR_FSYNC)";
    case SQLITE_IOERR_DIR_FSYNC:
      return " (directory fsync failed, SQLITE_IOERR_DIR_FSYNC)";
    case SQLITE_IOERR_TRUNCATE:
      return " (truncate failed, SQLITE_IOERR_TRUNCATE)";
    case SQLITE_IOERR_FSTAT:
      return " (fstat failed, SQLITE_IOERR_FSTAT)";
    case SQLITE_IOERR_DELETE:
      return " (delete failed, SQLITE_IOERR_DELETE)";
    case SQLITE_IOERR_SHMOPEN:
    case SQLITE_IOERR_SHMSIZE:
    case SQLITE_IOERR_SHMMAP:
      return " (the WAL index -shm file failed, extended code " + std::to_string(rc) + ")";
    default:
      return " (extended code " + std::to_string(rc) + ")";
  }
}

[[noreturn]] void throw_error(const std::string& label, std::string_view sql, int rc,
                              const char* message, sqlite3* db) {
  std::string text = label + ": SQLite error in `" + shorten(sql) +
                     "`: " + (message != nullptr ? message : sqlite3_errstr(rc)) + os_error(db, rc);
  const int primary = rc & 0xFF;
  if (primary == SQLITE_CORRUPT || primary == SQLITE_NOTADB) {
    text += " (the catalogue file is corrupt or not an SQLite database)";
  }
  if (environment_failure(rc)) throw EnvironmentError(text);
  throw InputError(text);
}

}  // namespace

Database::Database(const std::string& file, int flags, std::string label)
    : label_(std::move(label)) {
  const int rc = sqlite3_open_v2(file.c_str(), &db_, flags | SQLITE_OPEN_EXRESCODE, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message =
        (db_ != nullptr ? sqlite3_errmsg(db_) : sqlite3_errstr(rc)) + os_error(db_, rc);
    sqlite3_close_v2(db_);
    db_ = nullptr;
    const std::string text = label_ + ": cannot open the catalogue: " + message;
    if (environment_failure(rc)) throw EnvironmentError(text);
    throw InputError(text);
  }
  sqlite3_extended_result_codes(db_, 1);
}

Database::~Database() { sqlite3_close_v2(db_); }

void Database::exec(std::string_view sql) {
  const std::string text(sql);
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    std::string copy = message != nullptr ? message : sqlite3_errstr(rc);
    sqlite3_free(message);
    throw_error(label_, sql, rc, copy.c_str(), db_);
  }
}

std::int64_t Database::query_int(const char* sql) {
  Statement s(*this, sql);
  if (!s.step()) throw InputError(label_ + ": `" + sql + "` returned no row");
  return s.column_int(0);
}

std::string Database::query_text(const char* sql) {
  Statement s(*this, sql);
  std::string text;
  while (s.step()) {
    if (!text.empty()) text += '\n';
    text += s.column_text(0);
  }
  return text;
}

void Database::fail(std::string_view sql, int rc) const {
  throw_error(label_, sql, rc, sqlite3_errmsg(db_), db_);
}

Statement::Statement(Database& db, const char* sql) : db_(db), sql_(sql) {
  const int rc = sqlite3_prepare_v3(db.get(), sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr);
  if (rc != SQLITE_OK) db.fail(sql, rc);
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

void Statement::bind(int index, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, index, value);
  if (rc != SQLITE_OK) db_.fail(sql_, rc);
}

void Statement::bind(int index, double value) {
  const int rc = sqlite3_bind_double(stmt_, index, value);
  if (rc != SQLITE_OK) db_.fail(sql_, rc);
}

void Statement::bind(int index, std::string_view text) {
  const int rc =
      sqlite3_bind_text64(stmt_, index, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8);
  if (rc != SQLITE_OK) db_.fail(sql_, rc);
}

void Statement::bind_blob(int index, std::span<const std::byte> bytes) {
  // A zero-length blob must still be a blob, not NULL: pass a non-null pointer.
  static const std::byte kEmpty{};
  const void* data = bytes.empty() ? &kEmpty : bytes.data();
  const int rc = sqlite3_bind_blob64(stmt_, index, data, bytes.size(), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) db_.fail(sql_, rc);
}

void Statement::bind_null(int index) {
  const int rc = sqlite3_bind_null(stmt_, index);
  if (rc != SQLITE_OK) db_.fail(sql_, rc);
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  db_.fail(sql_, rc);
}

void Statement::run() {
  if (step()) throw InputError(db_.label() + ": `" + sql_ + "` returned a row unexpectedly");
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::is_null(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

std::int64_t Statement::column_int(int column) const { return sqlite3_column_int64(stmt_, column); }

double Statement::column_double(int column) const { return sqlite3_column_double(stmt_, column); }

std::string Statement::column_text(int column) const {
  const auto* text = sqlite3_column_text(stmt_, column);
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return text != nullptr ? std::string(reinterpret_cast<const char*>(text), bytes) : std::string();
}

std::vector<std::byte> Statement::column_blob(int column) const {
  const void* data = sqlite3_column_blob(stmt_, column);
  const int bytes = sqlite3_column_bytes(stmt_, column);
  std::vector<std::byte> out(static_cast<std::size_t>(bytes));
  if (bytes > 0) std::memcpy(out.data(), data, out.size());
  return out;
}

}  // namespace hapstate::catalogue_detail
