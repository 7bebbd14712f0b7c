// PRIVATE to the catalogue module: the schema migrations schema/NNNN_*.sql, embedded into the
// library at build time (libstate/catalogue/CMakeLists.txt generates schema_sql.cc).
#pragma once

#include <span>

namespace hapstate::catalogue_detail {

struct Migration {
  int version;            // NNNN of the file name; versions run 1, 2, ... without gaps
  const char* file_name;  // e.g. "0001_initial.sql"
  const char* sql;        // the file's text
};

// All migrations, ascending by version.
std::span<const Migration> embedded_migrations();

}  // namespace hapstate::catalogue_detail
