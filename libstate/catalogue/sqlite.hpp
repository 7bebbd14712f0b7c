// PRIVATE to the catalogue module (named .hpp so it is not installed with the public *.h
// headers: it exposes sqlite3). SQLite wrapped once: every failing call throws InputError
// with the database file, the SQL text and SQLite's message.
#pragma once

#include <sqlite3.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hapstate::catalogue_detail {

// One sqlite3 connection. Move-less; owned through a unique_ptr.
class Database {
 public:
  // Opens `file` with sqlite3_open_v2 `flags` (SQLITE_OPEN_*). `label` names it in messages.
  Database(const std::string& file, int flags, std::string label);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  sqlite3* get() const { return db_; }
  const std::string& label() const { return label_; }

  // Runs one or more statements without results (DDL, PRAGMA, BEGIN/COMMIT).
  void exec(std::string_view sql);
  // Runs a query returning one integer (e.g. "PRAGMA user_version").
  std::int64_t query_int(const char* sql);
  // Runs a query returning text rows, joined by '\n' (e.g. "PRAGMA integrity_check").
  std::string query_text(const char* sql);

  // Throws InputError for the last error of this connection while running `sql`.
  [[noreturn]] void fail(std::string_view sql, int rc) const;

 private:
  sqlite3* db_ = nullptr;
  std::string label_;
};

// A prepared statement, prepared once and reused: bind (1-based), step, read columns
// (0-based), reset.
class Statement {
 public:
  Statement(Database& db, const char* sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int index, std::int64_t value);
  void bind(int index, int value) { bind(index, static_cast<std::int64_t>(value)); }
  void bind(int index, double value);
  void bind(int index, std::string_view text);
  void bind_blob(int index, std::span<const std::byte> bytes);
  void bind_null(int index);

  // Executes one step: true if a row is available, false when done. Throws on error.
  bool step();
  // step() that must finish without a row (INSERT, UPDATE).
  void run();
  void reset();  // ready for new bindings

  bool is_null(int column) const;
  std::int64_t column_int(int column) const;
  double column_double(int column) const;
  std::string column_text(int column) const;
  std::vector<std::byte> column_blob(int column) const;

  const char* sql() const { return sql_; }

 private:
  Database& db_;
  sqlite3_stmt* stmt_ = nullptr;
  const char* sql_;
};

// Resets a statement when leaving scope, so an exception never leaves it mid-step.
class StatementUse {
 public:
  explicit StatementUse(Statement& s) : s_(s) {}
  ~StatementUse() { s_.reset(); }
  StatementUse(const StatementUse&) = delete;
  StatementUse& operator=(const StatementUse&) = delete;
  Statement* operator->() const { return &s_; }
  Statement& operator*() const { return s_; }

 private:
  Statement& s_;
};

}  // namespace hapstate::catalogue_detail
