// PRIVATE to the scene module (named .hpp so it is not installed with the public *.h headers:
// it exposes toml++ types). Typed, located access to one TOML table of the scene file; every
// problem (wrong type, out of range, unknown key) is recorded in a Diagnostics, never thrown.
#pragma once

#include "scene/diagnostics.h"
#include "scene/scene.h"

#include <toml++/toml.h>

#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace hapstate::scene_detail {

// A closed or open numeric interval, for range checks and their messages.
struct Interval {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = true;
  bool hi_open = true;

  bool contains(double v) const;
  std::string describe() const;  // "must be > 0", "must be in (-1, 0.5)", "must be in [1, 1000]"
};
Interval positive();
Interval non_negative();
Interval closed(double lo, double hi);
Interval open(double lo, double hi);

// Short TOML rendering of a node for messages (truncated when long).
std::string render(const toml::node& node);
// "a string", "an integer", ... for messages.
std::string type_phrase(const toml::node& node);
// Line of a node (0 if toml++ has no position for it).
int line_of(const toml::node& node);

class TableReader {
 public:
  // `name` is the dotted name of the table for messages ("material", "fixed[0]",
  // "fixed[0].plane"; empty for the root).
  TableReader(const toml::table& table, std::string name, Diagnostics& diagnostics);

  // Records every key not in `allowed` as an unknown key (or unknown table, for a table or
  // an array of tables), with a "did you mean" hint.
  void allow_only(std::initializer_list<std::string_view> allowed) const;

  bool has(std::string_view key) const { return table_.get(key) != nullptr; }
  const toml::node* get(std::string_view key) const { return table_.get(key); }
  int line() const { return line_of(table_); }
  // Line of key's value, or of the table when absent.
  int line(std::string_view key) const;
  const std::string& name() const { return name_; }
  std::string full_name(std::string_view key) const;
  Diagnostics& diagnostics() const { return diagnostics_; }

  // Records "missing key 'name.key'" at the table's line.
  void missing(std::string_view key, std::string_view hint = {}) const;
  // Records "key 'name.key' = <value>: <message>" at the value's line.
  void bad(std::string_view key, std::string_view message) const;

  // Typed readers: nullopt if absent (no problem recorded) or invalid (problem recorded).
  std::optional<double> number(std::string_view key, const Interval& range = {}) const;
  std::optional<int> integer(std::string_view key, const Interval& range = {}) const;
  std::optional<std::string> string(std::string_view key) const;
  std::optional<Eigen::Vector3d> point(std::string_view key) const;  // [x, y, z]
  std::optional<Box> box(std::string_view key) const;                // [[min], [max]]
  std::optional<DofMask> dofs(std::string_view key) const;           // subset of "xyz"
  // A sub-table (inline or not); records a type problem if `key` is something else.
  const toml::table* table(std::string_view key) const;

 private:
  std::optional<double> number_of(const toml::node& node) const;
  std::optional<Eigen::Vector3d> point_of(const toml::node& node) const;

  const toml::table& table_;
  std::string name_;
  Diagnostics& diagnostics_;
};

}  // namespace hapstate::scene_detail
