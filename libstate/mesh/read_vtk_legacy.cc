// Legacy VTK (.vtk) UNSTRUCTURED_GRID, ASCII or BINARY (big-endian). CELLS in the old
// "count+ids" layout or the VTK 5.1 OFFSETS/CONNECTIVITY layout. Integer one-component cell
// data (SCALARS or FIELD arrays) become groups "<array>:<value>"; other attribute data is skipped.
#include "mesh/binary.h"
#include "mesh/readers.h"
#include "mesh/text_cursor.h"
#include "mesh/vtk_common.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

namespace hapstate {
namespace {

struct ValueType {
  int size = 0;
  bool integral = false;
  bool is_signed = true;
};

ValueType value_type(TextCursor& c, std::string_view name) {
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char ch) { return std::tolower(ch); });
  if (n == "float") return {4, false, true};
  if (n == "double") return {8, false, true};
  if (n == "char") return {1, true, true};
  if (n == "unsigned_char") return {1, true, false};
  if (n == "short") return {2, true, true};
  if (n == "unsigned_short") return {2, true, false};
  if (n == "int" || n == "vtktypeint32") return {4, true, true};
  if (n == "unsigned_int" || n == "vtktypeuint32") return {4, true, false};
  if (n == "long" || n == "vtktypeint64" || n == "vtkidtype") return {8, true, true};
  if (n == "unsigned_long" || n == "vtktypeuint64") return {8, true, false};
  c.fail_expected("a VTK data type (float, double, int, unsigned_char, long, vtktypeint64, ...)",
                  name);
}

// Reads `count` numbers of `type`; integers go to `ints` (if not null), all to `reals` (if not
// null). `lines` (ASCII only, if not null) gets each value's line.
class ValueReader {
 public:
  ValueReader(TextCursor& c, bool binary) : c_(c), binary_(binary) {}

  void read(const ValueType& type, std::size_t count, std::string_view what,
            std::vector<long long>* ints, std::vector<double>* reals,
            std::vector<int>* lines = nullptr) {
    const std::size_t fits = std::min(count, c_.capacity(binary_ ? 1 : 2));  // >= 1 byte / "0 "
    if (ints != nullptr) ints->reserve(ints->size() + fits);
    if (reals != nullptr) reals->reserve(reals->size() + fits);
    if (binary_) {
      c_.skip_line_end();
      if (count > (std::size_t{1} << 40))
        c_.fail("implausible array size " + std::to_string(count));
      const char* p = c_.take_bytes(count * static_cast<std::size_t>(type.size), what);
      const int line = c_.line();
      const bool swap = kHostLittleEndian;  // legacy VTK binary is big-endian
      for (std::size_t i = 0; i < count; ++i, p += type.size) {
        double real = 0;
        long long integer = 0;
        if (type.integral) {
          switch (type.size) {
            case 1:
              integer = type.is_signed ? static_cast<long long>(static_cast<signed char>(*p))
                                       : static_cast<long long>(static_cast<unsigned char>(*p));
              break;
            case 2:
              integer = type.is_signed ? load_binary<std::int16_t>(p, swap)
                                       : load_binary<std::uint16_t>(p, swap);
              break;
            case 4:
              integer = type.is_signed ? load_binary<std::int32_t>(p, swap)
                                       : load_binary<std::uint32_t>(p, swap);
              break;
            default:
              integer = type.is_signed
                            ? load_binary<std::int64_t>(p, swap)
                            : static_cast<long long>(load_binary<std::uint64_t>(p, swap));
              break;
          }
          real = static_cast<double>(integer);
        } else {
          real = type.size == 4 ? static_cast<double>(load_binary<float>(p, swap))
                                : load_binary<double>(p, swap);
        }
        if (ints != nullptr) ints->push_back(integer);
        if (reals != nullptr) reals->push_back(real);
        if (lines != nullptr) lines->push_back(line);
      }
      return;
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (type.integral) {
        const long long v = c_.read_int(what);
        if (ints != nullptr) ints->push_back(v);
        if (reals != nullptr) reals->push_back(static_cast<double>(v));
      } else {
        const double v = c_.read_double(what);
        if (reals != nullptr) reals->push_back(v);
      }
      if (lines != nullptr) lines->push_back(c_.line());
    }
  }

 private:
  TextCursor& c_;
  bool binary_;
};

std::string upper(std::string_view s) {
  std::string u(s);
  std::transform(u.begin(), u.end(), u.begin(), [](unsigned char ch) { return std::toupper(ch); });
  return u;
}

long long read_count(TextCursor& c, std::string_view what) {
  const long long n = c.read_int(what);
  if (n < 0 || n > (1LL << 40))
    c.fail("expected a non-negative " + std::string(what) + ", got " + std::to_string(n));
  return n;
}

}  // namespace

RawMesh read_vtk_legacy(std::string_view text, const std::string& source, std::string* format) {
  TextCursor c(text, source);
  RawMesh mesh;
  mesh.source = source;
  const std::string_view header = c.rest_of_line();
  if (header.rfind("# vtk DataFile Version", 0) != 0) {
    c.fail_expected("'# vtk DataFile Version x.x' (legacy VTK header) on the first line", header);
  }
  c.skip_line_end();
  c.rest_of_line();  // title
  c.skip_line_end();
  const std::string mode = upper(c.token("ASCII or BINARY"));
  if (mode != "ASCII" && mode != "BINARY") c.fail_expected("ASCII or BINARY", mode);
  const bool binary = mode == "BINARY";
  *format = binary ? "vtk-legacy-binary" : "vtk-legacy";
  c.expect("DATASET");
  const std::string dataset = upper(c.token("dataset type"));
  if (dataset != "UNSTRUCTURED_GRID")
    c.fail_expected("UNSTRUCTURED_GRID (only unstructured grids hold tets)", dataset);

  ValueReader values(c, binary);
  VtkCells cells;
  std::vector<int> conn_lines;  // line of each connectivity entry
  int cells_line = 0;
  int types_line = 0;
  long long num_cells = -1;
  long long num_points = -1;
  // Attribute section: 0 = none yet, 1 = CELL_DATA, 2 = POINT_DATA.
  int attributes = 0;
  long long attribute_count = 0;

  const auto read_attribute_array = [&](const std::string& name, long long components,
                                        long long tuples, const ValueType& type,
                                        std::string_view what) {
    const std::size_t count = static_cast<std::size_t>(components * tuples);
    if (attributes == 1 && type.integral && components == 1) {
      std::vector<long long> v;
      values.read(type, count, what, &v, nullptr);
      cells.labels.emplace_back(name, std::move(v));
    } else {
      values.read(type, count, what, nullptr, nullptr);
    }
  };

  while (!c.at_end()) {
    const std::string keyword = upper(c.token("section keyword"));
    if (keyword == "POINTS") {
      if (num_points >= 0) c.fail("second POINTS section (expected one)");
      num_points = read_count(c, "number of points");
      if (num_points > (1LL << 31) - 1) c.fail("too many points");
      const ValueType type = value_type(c, c.token("point data type"));
      values.read(type, 3 * static_cast<std::size_t>(num_points), "point coordinate", nullptr,
                  &mesh.xyz);
    } else if (keyword == "CELLS") {
      if (num_cells >= 0) c.fail("second CELLS section (expected one)");
      cells_line = c.line();
      const long long a = read_count(c, "number of cells");
      const long long b = read_count(c, "cell list size");
      if (upper(c.peek()) == "OFFSETS") {  // VTK 5.1: a offsets, b connectivity entries
        c.token("OFFSETS");
        if (a < 1) c.fail("expected at least one offset (number of cells + 1)");
        num_cells = a - 1;
        const ValueType ot = value_type(c, c.token("offsets data type"));
        values.read(ot, static_cast<std::size_t>(a), "cell offset", &cells.offsets, nullptr);
        const std::string conn = upper(c.token("CONNECTIVITY"));
        if (conn != "CONNECTIVITY") c.fail_expected("CONNECTIVITY after the OFFSETS array", conn);
        const ValueType ct = value_type(c, c.token("connectivity data type"));
        values.read(ct, static_cast<std::size_t>(b), "cell point id", &cells.connectivity, nullptr,
                    &conn_lines);
        if (cells.offsets.front() != 0 || cells.offsets.back() != b) {
          c.fail_at(cells_line, "cell offsets must start at 0 and end at the connectivity size " +
                                    std::to_string(b));
        }
        for (long long i = 0; i < num_cells; ++i) {
          if (cells.offsets[static_cast<std::size_t>(i + 1)] <
              cells.offsets[static_cast<std::size_t>(i)]) {
            c.fail_at(cells_line, "cell offsets decrease at cell " + std::to_string(i));
          }
        }
      } else {  // legacy: per cell "n id1 .. idn", b numbers in total
        num_cells = a;
        cells.offsets.reserve(std::min(static_cast<std::size_t>(a), c.capacity(2)) + 1);
        cells.connectivity.reserve(
            std::min(static_cast<std::size_t>(b - std::min(a, b)), c.capacity(2)));
        cells.offsets.push_back(0);
        if (binary) {
          std::vector<long long> raw;
          values.read({4, true, true}, static_cast<std::size_t>(b), "cell list", &raw, nullptr);
          std::size_t k = 0;
          for (long long i = 0; i < a; ++i) {
            const long long n = k < raw.size() ? raw[k] : -1;
            if (n < 0 || k + 1 + static_cast<std::size_t>(n) > raw.size()) {
              c.fail_at(cells_line, "cell list size " + std::to_string(b) + " does not match the " +
                                        std::to_string(a) + " cells (corrupt cell " +
                                        std::to_string(i) + ")");
            }
            cells.connectivity.insert(cells.connectivity.end(),
                                      raw.begin() + static_cast<long long>(k) + 1,
                                      raw.begin() + static_cast<long long>(k) + 1 + n);
            k += 1 + static_cast<std::size_t>(n);
            cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
          }
          conn_lines.assign(cells.connectivity.size(), cells_line);
          if (k != raw.size())
            c.fail_at(cells_line,
                      "cell list size " + std::to_string(b) + " does not match its cells");
        } else {
          long long used = 0;
          for (long long i = 0; i < a; ++i) {
            const long long n = c.read_int("number of points of the cell");
            if (n < 0 || n > 1000)
              c.fail("expected a small number of cell points, got " + std::to_string(n));
            for (long long k = 0; k < n; ++k) {
              cells.connectivity.push_back(c.read_int("cell point id"));
              conn_lines.push_back(c.line());
            }
            cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
            used += 1 + n;
          }
          if (used != b) {
            c.fail("the " + std::to_string(a) + " cells hold " + std::to_string(used) +
                   " numbers but CELLS declares " + std::to_string(b) + " (wrong cell count?)");
          }
        }
      }
    } else if (keyword == "CELL_TYPES") {
      types_line = c.line();
      const long long n = read_count(c, "number of cell types");
      if (n != num_cells) {
        c.fail("CELL_TYPES count " + std::to_string(n) + " differs from the " +
               std::to_string(num_cells) + " cells of CELLS (or CELLS is missing)");
      }
      values.read({4, true, true}, static_cast<std::size_t>(n), "cell type", &cells.types, nullptr);
    } else if (keyword == "CELL_DATA" || keyword == "POINT_DATA") {
      attributes = keyword == "CELL_DATA" ? 1 : 2;
      attribute_count = read_count(c, "number of attribute tuples");
      if (attributes == 1 && attribute_count != num_cells) {
        c.fail("CELL_DATA count " + std::to_string(attribute_count) +
               " differs from the number of cells " + std::to_string(num_cells));
      }
    } else if (attributes != 0 && keyword == "SCALARS") {
      const std::string name(c.token("scalars name"));
      const ValueType type = value_type(c, c.token("scalars data type"));
      long long components = 1;
      if (upper(c.peek()) != "LOOKUP_TABLE") components = c.read_int("number of components");
      c.expect("LOOKUP_TABLE");
      c.token("lookup table name");
      read_attribute_array(name, components, attribute_count, type, "scalar value");
    } else if (attributes != 0 && keyword == "FIELD") {
      c.token("field name");
      const long long arrays = read_count(c, "number of field arrays");
      for (long long i = 0; i < arrays; ++i) {
        const std::string name(c.token("field array name"));
        const long long components = read_count(c, "number of components");
        const long long tuples = read_count(c, "number of tuples");
        const ValueType type = value_type(c, c.token("field array data type"));
        read_attribute_array(name, components, tuples, type, "field value");
        if (upper(c.peek()) == "METADATA") {
          c.token("METADATA");
          while (!c.at_end() && !c.rest_of_line().empty()) c.skip_line_end();
        }
      }
    } else if (attributes != 0 &&
               (keyword == "VECTORS" || keyword == "NORMALS" || keyword == "TENSORS" ||
                keyword == "TENSORS6" || keyword == "GLOBAL_IDS" || keyword == "PEDIGREE_IDS")) {
      c.token("array name");
      const ValueType type = value_type(c, c.token("data type"));
      const long long components = keyword == "TENSORS"                                     ? 9
                                   : keyword == "TENSORS6"                                  ? 6
                                   : (keyword == "GLOBAL_IDS" || keyword == "PEDIGREE_IDS") ? 1
                                                                                            : 3;
      values.read(type, static_cast<std::size_t>(components * attribute_count), "attribute value",
                  nullptr, nullptr);
    } else if (attributes != 0 && keyword == "TEXTURE_COORDINATES") {
      c.token("array name");
      const long long dim = read_count(c, "texture dimension");
      const ValueType type = value_type(c, c.token("data type"));
      values.read(type, static_cast<std::size_t>(dim * attribute_count), "attribute value", nullptr,
                  nullptr);
    } else if (keyword == "METADATA") {
      while (!c.at_end() && !c.rest_of_line().empty()) c.skip_line_end();
    } else if (attributes != 0) {
      mesh.warnings.push_back(c.where() +
                              ": ignored the rest of the file from attribute keyword '" +
                              printable(keyword) + "' (not needed for the mesh)");
      break;
    } else {
      c.fail_expected("POINTS, CELLS, CELL_TYPES, CELL_DATA or POINT_DATA", keyword);
    }
  }
  if (num_points < 0) c.fail("truncated file: no POINTS section");
  if (num_cells < 0) c.fail("truncated file: no CELLS section");
  if (static_cast<long long>(cells.types.size()) != num_cells)
    c.fail("truncated file: no CELL_TYPES section");
  for (const auto& [name, v] : cells.labels) {
    if (static_cast<long long>(v.size()) != num_cells)
      c.fail("cell data array '" + name + "' has the wrong size");
  }
  const auto where = [&](std::size_t cell) {
    const long long first = cells.offsets[cell];
    const int line =
        first < static_cast<long long>(conn_lines.size()) && cells.offsets[cell + 1] > first
            ? conn_lines[static_cast<std::size_t>(first)]
            : (types_line > 0 ? types_line : cells_line);
    return c.where(line);
  };
  add_vtk_cells(cells, 0, static_cast<int>(num_points), where, &mesh);
  return mesh;
}

}  // namespace hapstate
