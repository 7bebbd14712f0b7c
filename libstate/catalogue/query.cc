// Catalogue::query_read_only: the read-only SQL passthrough of hapstate-inspect.
#include "catalogue/catalogue_impl.hpp"
#include "util/error.h"

#include <cctype>
#include <cstring>
#include <initializer_list>

namespace hapstate {
namespace {

bool equals_ignoring_case(const char* a, const char* b) {
  for (; *a != '\0' && *b != '\0'; ++a, ++b)
    if (std::tolower(static_cast<unsigned char>(*a)) !=
        std::tolower(static_cast<unsigned char>(*b)))
      return false;
  return *a == *b;
}

// Whether a PRAGMA only reads. With an argument, only the schema and check pragmas, whose
// argument names a table or index or a limit (PRAGMA table_info(configuration)); any other
// pragma with an argument sets something (user_version = 7). Without one, every pragma reads
// except those that act (checkpoint, optimize, free memory or pages).
bool pragma_reads(const char* name, bool has_argument) {
  if (has_argument) {
    for (const char* reader :
         {"table_info", "table_xinfo", "table_list", "index_info", "index_xinfo", "index_list",
          "foreign_key_list", "foreign_key_check", "integrity_check", "quick_check"})
      if (equals_ignoring_case(name, reader)) return true;
    return false;
  }
  for (const char* actor : {"optimize", "wal_checkpoint", "shrink_memory", "incremental_vacuum"})
    if (equals_ignoring_case(name, actor)) return false;
  return true;
}

// Called by SQLite for every action a statement being prepared would take. Denies whatever
// changes the connection or the files even though sqlite3_stmt_readonly calls it a read.
int deny_non_reads(void* reason_out, int action, const char* arg1, const char* arg2, const char*,
                   const char*) {
  auto* reason = static_cast<std::string*>(reason_out);
  switch (action) {
    case SQLITE_ATTACH:
    case SQLITE_DETACH:
      *reason = "ATTACH / DETACH";
      return SQLITE_DENY;
    case SQLITE_TRANSACTION:
    case SQLITE_SAVEPOINT:
      *reason = "transaction control";
      return SQLITE_DENY;
    case SQLITE_PRAGMA:
      if (arg1 == nullptr || !pragma_reads(arg1, arg2 != nullptr)) {
        *reason = std::string("PRAGMA ") + (arg1 != nullptr ? arg1 : "") +
                  (arg2 != nullptr ? " with a value" : " changes state");
        return SQLITE_DENY;
      }
      return SQLITE_OK;
    case SQLITE_FUNCTION:
      if (arg2 != nullptr && std::strcmp(arg2, "load_extension") == 0) {
        *reason = "load_extension";
        return SQLITE_DENY;
      }
      return SQLITE_OK;
    default:
      return SQLITE_OK;
  }
}

// Clears the authorizer and finalises the statement on every path.
struct PreparedQuery {
  sqlite3* db;
  sqlite3_stmt* stmt = nullptr;
  ~PreparedQuery() {
    sqlite3_finalize(stmt);
    sqlite3_set_authorizer(db, nullptr, nullptr);
  }
};

bool only_blank(const char* tail) {
  for (; *tail != '\0'; ++tail) {
    if (!std::isspace(static_cast<unsigned char>(*tail)) && *tail != ';') return false;
  }
  return true;
}

QueryValue column_value(sqlite3_stmt* stmt, int c) {
  switch (sqlite3_column_type(stmt, c)) {
    case SQLITE_INTEGER:
      return static_cast<std::int64_t>(sqlite3_column_int64(stmt, c));
    case SQLITE_FLOAT:
      return sqlite3_column_double(stmt, c);
    case SQLITE_TEXT: {
      const auto* text = sqlite3_column_text(stmt, c);
      return std::string(reinterpret_cast<const char*>(text),
                         static_cast<std::size_t>(sqlite3_column_bytes(stmt, c)));
    }
    case SQLITE_BLOB: {
      const auto* bytes = static_cast<const std::byte*>(sqlite3_column_blob(stmt, c));
      return std::vector<std::byte>(bytes, bytes + sqlite3_column_bytes(stmt, c));
    }
    default:
      return std::monostate{};
  }
}

}  // namespace

QueryResult Catalogue::query_read_only(std::string_view sql) {
  const std::string text(sql);
  const std::string& label = impl_->label();
  sqlite3* db = impl_->db->get();
  std::string denied;
  PreparedQuery q{db};
  sqlite3_set_authorizer(db, deny_non_reads, &denied);
  const char* tail = nullptr;
  const int rc =
      sqlite3_prepare_v2(db, text.c_str(), static_cast<int>(text.size()), &q.stmt, &tail);
  if (rc != SQLITE_OK) {
    if (!denied.empty())
      throw InputError(label + ": refused (" + denied + "): read-only queries only");
    impl_->db->fail(text, rc);
  }
  if (q.stmt == nullptr) throw InputError(label + ": empty SQL statement");
  if (tail != nullptr && !only_blank(tail)) {
    throw InputError(label + ": refused: give one SQL statement at a time");
  }
  if (!sqlite3_stmt_readonly(q.stmt)) {
    throw InputError(label + ": refused: the statement could write (read-only queries only)");
  }
  sqlite3_set_authorizer(db, nullptr, nullptr);

  QueryResult result;
  const int columns = sqlite3_column_count(q.stmt);
  for (int c = 0; c < columns; ++c) {
    const char* name = sqlite3_column_name(q.stmt, c);
    result.columns.emplace_back(name != nullptr ? name : "");
  }
  for (;;) {
    const int step = sqlite3_step(q.stmt);
    if (step == SQLITE_DONE) break;
    if (step != SQLITE_ROW) impl_->db->fail(text, step);
    auto& row = result.rows.emplace_back();
    row.reserve(columns);
    for (int c = 0; c < columns; ++c) row.push_back(column_value(q.stmt, c));
  }
  return result;
}

}  // namespace hapstate
