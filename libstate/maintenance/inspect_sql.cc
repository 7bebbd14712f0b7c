// hapstate-inspect sql: the read-only passthrough.
#include "maintenance/inspect_common.hpp"

#include <sstream>
#include <variant>

namespace hapstate {

using namespace inspect_detail;

namespace {

std::string hex(const std::vector<std::byte>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::byte b : bytes) {
    s += kDigits[std::to_integer<int>(b) >> 4];
    s += kDigits[std::to_integer<int>(b) & 15];
  }
  return s;
}

// NULL -> null, INTEGER / REAL -> number, TEXT -> string, BLOB -> {"blob": "<hex>"}.
Json value_json(const QueryValue& v) {
  return std::visit(
      [](const auto& x) -> Json {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>)
          return nullptr;
        else if constexpr (std::is_same_v<T, std::vector<std::byte>>)
          return {{"blob", hex(x)}};
        else
          return x;
      },
      v);
}

std::string value_text(const QueryValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>)
          return "NULL";
        else if constexpr (std::is_same_v<T, std::vector<std::byte>>)
          return "x'" + hex(x) + "'";
        else if constexpr (std::is_same_v<T, std::string>)
          return x;
        else if constexpr (std::is_same_v<T, double>)
          return num(x);
        else
          return std::to_string(x);
      },
      v);
}

}  // namespace

InspectOutput inspect_sql(const StateDir& dir, std::string_view sql) {
  Catalogue cat = open_read_only(dir);
  const QueryResult r = cat.query_read_only(sql);
  Json rows = Json::array();
  std::ostringstream s;
  for (std::size_t c = 0; c < r.columns.size(); ++c) s << (c ? "\t" : "") << r.columns[c];
  s << "\n";
  for (const auto& row : r.rows) {
    Json jr = Json::array();
    for (std::size_t c = 0; c < row.size(); ++c) {
      jr.push_back(value_json(row[c]));
      s << (c ? "\t" : "") << value_text(row[c]);
    }
    s << "\n";
    rows.push_back(jr);
  }
  const Json j = {{"columns", r.columns}, {"rows", rows}};
  return {dump(j), s.str()};
}

}  // namespace hapstate
