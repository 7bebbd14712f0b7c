#include "scene/toml_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <vector>

namespace hapstate::scene_detail {
namespace {

std::string format_number(double v) {
  std::ostringstream os;
  os.precision(15);
  os << v;
  return os.str();
}

// Levenshtein distance, for "did you mean" hints.
int edit_distance(std::string_view a, std::string_view b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// A number (integer or float) or an error phrase.
std::optional<double> as_number(const toml::node& node, std::string* error) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) {
    if (!std::isfinite(f->get())) {
      *error = "must be a finite number";
      return std::nullopt;
    }
    return f->get();
  }
  *error = "expected a number, got " + type_phrase(node);
  return std::nullopt;
}

std::optional<Eigen::Vector3d> as_point(const toml::node& node, std::string* error) {
  const auto* array = node.as_array();
  if (array == nullptr || array->size() != 3) {
    *error = "expected an array of 3 numbers [x, y, z], got " +
             (array ? "an array of " + std::to_string(array->size()) + " element(s)"
                    : type_phrase(node));
    return std::nullopt;
  }
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k) {
    std::string element_error;
    const auto v = as_number(*array->get(static_cast<size_t>(k)), &element_error);
    if (!v) {
      *error = "element " + std::to_string(k) + ": " + element_error;
      return std::nullopt;
    }
    p[k] = *v;
  }
  return p;
}

}  // namespace

bool Interval::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Interval::describe() const {
  const bool lo_inf = std::isinf(lo), hi_inf = std::isinf(hi);
  if (lo_inf && hi_inf) return "must be a number";
  if (hi_inf) return std::string("must be ") + (lo_open ? "> " : ">= ") + format_number(lo);
  if (lo_inf) return std::string("must be ") + (hi_open ? "< " : "<= ") + format_number(hi);
  return "must be in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " +
         format_number(hi) + (hi_open ? ")" : "]");
}

Interval positive() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
Interval non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }
Interval closed(double lo, double hi) { return {lo, hi, false, false}; }
Interval open(double lo, double hi) { return {lo, hi, true, true}; }

namespace {

// Shortest decimal that reads back as v; integral values keep a ".0" so floats look like floats.
std::string render_float(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  std::string text(buffer, end);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

void render_into(const toml::node& node, std::string& out) {
  if (const auto* s = node.as_string()) {
    out += '"' + s->get() + '"';
  } else if (const auto* i = node.as_integer()) {
    out += std::to_string(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    out += render_float(f->get());
  } else if (const auto* b = node.as_boolean()) {
    out += b->get() ? "true" : "false";
  } else if (const auto* a = node.as_array()) {
    out += '[';
    for (size_t k = 0; k < a->size(); ++k) {
      if (k > 0) out += ", ";
      render_into(*a->get(k), out);
    }
    out += ']';
  } else if (node.is_table()) {
    out += "{...}";
  } else {
    std::ostringstream os;  // dates and times
    node.visit([&os](const auto& n) { os << n; });
    out += os.str();
  }
}

}  // namespace

std::string render(const toml::node& node) {
  std::string text;
  render_into(node, text);
  constexpr size_t kMaxLength = 60;
  if (text.size() > kMaxLength) text = text.substr(0, kMaxLength - 3) + "...";
  return text;
}

std::string type_phrase(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    default:
      return "nothing";
  }
}

int line_of(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

TableReader::TableReader(const toml::table& table, std::string name, Diagnostics& diagnostics)
    : table_(table), name_(std::move(name)), diagnostics_(diagnostics) {}

std::string TableReader::full_name(std::string_view key) const {
  return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
}

int TableReader::line(std::string_view key) const {
  const toml::node* node = table_.get(key);
  return node ? line_of(*node) : line();
}

void TableReader::allow_only(std::initializer_list<std::string_view> allowed) const {
  for (const auto& [key, node] : table_) {
    const std::string_view k = key.str();
    if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
    std::string list, best;
    int best_distance = 3;  // suggest only close matches
    for (std::string_view a : allowed) {
      list += (list.empty() ? "" : ", ") + std::string(a);
      const int d = edit_distance(k, a);
      if (d < best_distance) best_distance = d, best = std::string(a);
    }
    const auto* array = node.as_array();
    const bool is_table =
        node.is_table() || (array && !array->empty() && array->is_array_of_tables());
    std::string message =
        std::string(is_table ? "unknown table '" : "unknown key '") + full_name(k) + "'";
    if (!best.empty()) message += " (did you mean '" + best + "'?)";
    message += "; allowed: " + list;
    int line = static_cast<int>(key.source().begin.line);
    if (line == 0) line = line_of(node);
    // A close match is most likely a misspelling, and the cause of a "missing key" reported for
    // its correct spelling: it comes first.
    if (best.empty())
      diagnostics_.add(line, message);
    else
      diagnostics_.add_cause(line, message);
  }
}

void TableReader::missing(std::string_view key, std::string_view hint) const {
  std::string message = "missing key '" + full_name(key) + "'";
  if (!hint.empty()) message += " (" + std::string(hint) + ")";
  diagnostics_.add(line(), message);
}

void TableReader::bad(std::string_view key, std::string_view message) const {
  const toml::node* node = table_.get(key);
  std::string text = "key '" + full_name(key) + "'";
  if (node) text += " = " + render(*node);
  text += ": " + std::string(message);
  diagnostics_.add(line(key), text);
}

std::optional<double> TableReader::number(std::string_view key, const Interval& range) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  std::string error;
  const auto v = as_number(*node, &error);
  if (!v) {
    bad(key, error);
    return std::nullopt;
  }
  if (!range.contains(*v)) {
    bad(key, range.describe());
    return std::nullopt;
  }
  return v;
}

std::optional<int> TableReader::integer(std::string_view key, const Interval& range) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* i = node->as_integer();
  if (i == nullptr) {
    bad(key, "expected an integer, got " + type_phrase(*node));
    return std::nullopt;
  }
  const double v = static_cast<double>(i->get());
  if (!range.contains(v)) {
    bad(key, range.describe());
    return std::nullopt;
  }
  return static_cast<int>(i->get());
}

std::optional<std::string> TableReader::string(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* s = node->as_string();
  if (s == nullptr) {
    bad(key, "expected a string, got " + type_phrase(*node));
    return std::nullopt;
  }
  return s->get();
}

std::optional<Eigen::Vector3d> TableReader::point(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  std::string error;
  auto p = as_point(*node, &error);
  if (!p) bad(key, error);
  return p;
}

std::optional<Box> TableReader::box(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* array = node->as_array();
  if (array == nullptr || array->size() != 2) {
    bad(key, "expected [[x0, y0, z0], [x1, y1, z1]], got " +
                 (array ? "an array of " + std::to_string(array->size()) + " element(s)"
                        : type_phrase(*node)));
    return std::nullopt;
  }
  Box box;
  std::string error;
  const auto lo = as_point(*array->get(0), &error);
  if (!lo) {
    bad(key, "min corner: " + error);
    return std::nullopt;
  }
  const auto hi = as_point(*array->get(1), &error);
  if (!hi) {
    bad(key, "max corner: " + error);
    return std::nullopt;
  }
  box.min = *lo;
  box.max = *hi;
  for (int k = 0; k < 3; ++k) {
    if (!(box.min[k] < box.max[k])) {
      bad(key, std::string("min must be < max in every component (") + "xyz"[k] + ": " +
                   format_number(box.min[k]) + " >= " + format_number(box.max[k]) + ")");
      return std::nullopt;
    }
  }
  return box;
}

std::optional<DofMask> TableReader::dofs(std::string_view key) const {
  const auto text = string(key);
  if (!text) return std::nullopt;
  DofMask mask{false, false, false};
  if (text->empty()) {
    bad(key, "must name at least one of x, y, z");
    return std::nullopt;
  }
  for (char c : *text) {
    const int k = c == 'x' ? 0 : c == 'y' ? 1 : c == 'z' ? 2 : -1;
    if (k < 0) {
      bad(key, std::string("'") + c + "' is not a component; use letters from \"xyz\"");
      return std::nullopt;
    }
    if (mask[k]) {
      bad(key, std::string("component '") + c + "' repeated");
      return std::nullopt;
    }
    mask[k] = true;
  }
  return mask;
}

const toml::table* TableReader::table(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return nullptr;
  const auto* t = node->as_table();
  if (t == nullptr) bad(key, "expected a table, got " + type_phrase(*node));
  return t;
}

}  // namespace hapstate::scene_detail
