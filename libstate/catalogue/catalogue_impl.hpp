// PRIVATE to the catalogue module: the state behind Catalogue, shared by the per-table .cc
// files, and helpers to (de)serialise row fields.
#pragma once

#include "catalogue/catalogue.h"
#include "catalogue/sqlite.hpp"

#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

namespace hapstate {

struct Catalogue::Impl {
  std::filesystem::path file;
  std::unique_ptr<catalogue_detail::Database> db;
  int schema_version = 0;
  bool in_transaction = false;
  // Prepared once, on first use. Keyed by the address of the SQL literal in each .cc file.
  std::unordered_map<const char*, std::unique_ptr<catalogue_detail::Statement>> statements;

  catalogue_detail::Statement& statement(const char* sql) {
    auto& slot = statements[sql];
    if (!slot) slot = std::make_unique<catalogue_detail::Statement>(*db, sql);
    return *slot;
  }
  const std::string& label() const { return db->label(); }
};

namespace catalogue_detail {

// Makes one verb that writes several rows atomic, inside or outside a Transaction: SAVEPOINT
// on construction, RELEASE on release(), ROLLBACK TO + RELEASE when destroyed before.
class Savepoint {
 public:
  explicit Savepoint(Database& db) : db_(db) { db_.exec("SAVEPOINT hapstate_verb"); }
  ~Savepoint() {
    if (!released_) {
      sqlite3_exec(db_.get(), "ROLLBACK TO hapstate_verb; RELEASE hapstate_verb", nullptr, nullptr,
                   nullptr);
    }
  }
  Savepoint(const Savepoint&) = delete;
  Savepoint& operator=(const Savepoint&) = delete;
  void release() {
    db_.exec("RELEASE hapstate_verb");
    released_ = true;
  }

 private:
  Database& db_;
  bool released_ = false;
};

// Integer column `column` of the current row, which must lie in [lo, hi]: the schema CHECKs
// these ranges when rows are written, but a damaged file is read without the checks. Throws
// InputError "label: damaged catalogue: table.name = v, not in lo..hi".
int ranged_column(const Statement& s, int column, int lo, int hi, const std::string& label,
                  const char* name);

// float64 vectors stored as little-endian BLOBs (configuration.summary).
std::vector<std::byte> pack_doubles(std::span<const double> values);
std::vector<double> unpack_doubles(std::span<const std::byte> bytes, const std::string& where);

}  // namespace catalogue_detail
}  // namespace hapstate
