// Result of an ad-hoc read-only SQL query on the catalogue (Catalogue::query_read_only): the
// column names and every row, each value in SQLite's own storage class.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace hapstate {

// NULL, INTEGER, REAL, TEXT or BLOB.
using QueryValue =
    std::variant<std::monostate, std::int64_t, double, std::string, std::vector<std::byte>>;

struct QueryResult {
  std::vector<std::string> columns;
  std::vector<std::vector<QueryValue>> rows;  // each rows[r].size() == columns.size()
};

}  // namespace hapstate
