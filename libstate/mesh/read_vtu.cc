// VTK XML UnstructuredGrid (.vtu): DataArrays in ascii, base64 "binary" or appended (raw or
// base64) form, UInt32/UInt64 headers, optional zlib compression, one or more Pieces.
// Integer one-component CellData arrays become groups "<array>:<value>".
#include "mesh/binary.h"
#include "mesh/readers.h"
#include "mesh/text_cursor.h"
#include "mesh/vtk_common.h"
#include "mesh/vtu_bytes.h"
#include "mesh/xml_scan.h"
#include "util/error.h"

#include <cstdint>

namespace hapstate {
namespace {

struct ArrayType {
  int size = 0;
  bool integral = false;
  bool is_signed = true;
};

class VtuReader {
 public:
  VtuReader(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  RawMesh read(std::string* format) {
    doc_ = parse_xml(text_, source_);
    const XmlElement& root = doc_.root;
    if (root.name != "VTKFile")
      fail(root, "expected <VTKFile> as the root element, got <" + root.name + ">");
    const std::string* type = root.attribute("type");
    if (type == nullptr || *type != "UnstructuredGrid") {
      fail(root, "expected VTKFile type=\"UnstructuredGrid\", got \"" +
                     (type != nullptr ? *type : std::string()) + "\"");
    }
    const std::string* order = root.attribute("byte_order");
    const bool big = order != nullptr && *order == "BigEndian";
    swap_ = big == kHostLittleEndian;
    const std::string* header = root.attribute("header_type");
    header_size_ = 4;
    if (header != nullptr) {
      if (*header == "UInt64") {
        header_size_ = 8;
      } else if (*header != "UInt32") {
        fail(root, "expected header_type UInt32 or UInt64, got \"" + *header + "\"");
      }
    }
    const std::string* compressor = root.attribute("compressor");
    if (compressor != nullptr && !compressor->empty()) {
      if (*compressor != "vtkZLibDataCompressor") {
        fail(root, "unsupported compressor \"" + *compressor +
                       "\" (only vtkZLibDataCompressor; re-save uncompressed)");
      }
      zlib_ = true;
    }
    *format = "vtu";

    const XmlElement* grid = root.child("UnstructuredGrid");
    if (grid == nullptr) fail(root, "expected an <UnstructuredGrid> element");
    RawMesh mesh;
    mesh.source = source_;
    int pieces = 0;
    for (const XmlElement& piece : grid->children) {
      if (piece.name != "Piece") continue;
      ++pieces;
      read_piece(piece, &mesh);
    }
    if (pieces == 0) fail(*grid, "expected at least one <Piece>");
    return mesh;
  }

 private:
  [[noreturn]] void fail(const XmlElement& e, const std::string& message) const {
    fail_at(e.offset, message);
  }
  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const {
    throw InputError(source_ + ":" + std::to_string(doc_.line_at(offset)) + ": " + message);
  }

  long long count_attribute(const XmlElement& e, std::string_view key) const {
    const std::string* v = e.attribute(key);
    long long n = 0;
    if (v == nullptr || !parse_int(*v, &n) || n < 0) {
      fail(e, "expected a non-negative integer attribute " + std::string(key) + " on <" + e.name +
                  ">");
    }
    return n;
  }

  ArrayType array_type(const XmlElement& e) const {
    const std::string* t = e.attribute("type");
    const std::string name = t != nullptr ? *t : "";
    if (name == "Float32") return {4, false, true};
    if (name == "Float64") return {8, false, true};
    if (name == "Int8" || name == "Char") return {1, true, true};
    if (name == "UInt8") return {1, true, false};
    if (name == "Int16") return {2, true, true};
    if (name == "UInt16") return {2, true, false};
    if (name == "Int32") return {4, true, true};
    if (name == "UInt32") return {4, true, false};
    if (name == "Int64") return {8, true, true};
    if (name == "UInt64") return {8, true, false};
    fail(e, "expected a DataArray type (Float32, Float64, Int8..Int64, UInt8..UInt64), got \"" +
                name + "\"");
  }

  // Reads `count` values of DataArray `e` into ints and/or reals.
  void read_array(const XmlElement& e, std::size_t count, std::vector<long long>* ints,
                  std::vector<double>* reals) {
    const ArrayType type = array_type(e);
    const std::string* f = e.attribute("format");
    const std::string format = f != nullptr ? *f : "ascii";
    if (format == "ascii") {
      TextCursor c(e.text, source_, '\0', doc_.line_at(e.text_offset));
      for (std::size_t i = 0; i < count; ++i) {
        if (c.at_end()) {
          c.fail("DataArray holds only " + std::to_string(i) + " values, expected " +
                 std::to_string(count) + " (wrong count?)");
        }
        if (type.integral) {
          const long long v = c.read_int("integer value of DataArray");
          if (ints != nullptr) ints->push_back(v);
          if (reals != nullptr) reals->push_back(static_cast<double>(v));
        } else {
          const double v = c.read_double("number of DataArray");
          if (reals != nullptr) reals->push_back(v);
        }
      }
      if (!c.at_end())
        c.fail_expected(
            "end of DataArray after " + std::to_string(count) + " values (wrong count?)", c.peek());
      return;
    }
    std::string payload;
    std::string error;
    std::size_t where = e.offset;
    if (format == "binary") {
      ByteStream stream(e.text, true);
      where = e.text_offset;
      if (!read_vtk_block(stream, header_size_, swap_, zlib_, &payload, &error))
        fail_at(where, error);
    } else if (format == "appended") {
      const long long offset = count_attribute(e, "offset");
      if (doc_.appended.data() == nullptr)
        fail(e, "format=\"appended\" but the file has no <AppendedData>");
      const bool base64 = doc_.appended_encoding == "base64";
      if (!base64 && doc_.appended_encoding != "raw") {
        fail(e, "expected AppendedData encoding raw or base64, got \"" + doc_.appended_encoding +
                    "\"");
      }
      if (static_cast<std::size_t>(offset) > doc_.appended.size())
        fail(e, "appended data offset beyond the end of the file (truncated?)");
      ByteStream stream(doc_.appended.substr(static_cast<std::size_t>(offset)), base64);
      if (!read_vtk_block(stream, header_size_, swap_, zlib_, &payload, &error))
        fail(e, error + " (appended data)");
    } else {
      fail(e, "expected DataArray format ascii, binary or appended, got \"" + format + "\"");
    }
    if (payload.size() != count * static_cast<std::size_t>(type.size)) {
      fail_at(where, "expected " + std::to_string(count) + " values (" +
                         std::to_string(count * type.size) + " bytes) in binary DataArray, got " +
                         std::to_string(payload.size()) + " bytes (wrong count?)");
    }
    const char* p = payload.data();
    for (std::size_t i = 0; i < count; ++i, p += type.size) {
      long long integer = 0;
      double real = 0;
      if (type.integral) {
        switch (type.size) {
          case 1:
            integer = type.is_signed ? static_cast<long long>(static_cast<signed char>(*p))
                                     : static_cast<long long>(static_cast<unsigned char>(*p));
            break;
          case 2:
            integer = type.is_signed ? load_binary<std::int16_t>(p, swap_)
                                     : load_binary<std::uint16_t>(p, swap_);
            break;
          case 4:
            integer = type.is_signed ? load_binary<std::int32_t>(p, swap_)
                                     : load_binary<std::uint32_t>(p, swap_);
            break;
          default:
            integer = type.is_signed ? load_binary<std::int64_t>(p, swap_)
                                     : static_cast<long long>(load_binary<std::uint64_t>(p, swap_));
            break;
        }
        real = static_cast<double>(integer);
      } else {
        real = type.size == 4 ? static_cast<double>(load_binary<float>(p, swap_))
                              : load_binary<double>(p, swap_);
      }
      if (ints != nullptr) ints->push_back(integer);
      if (reals != nullptr) reals->push_back(real);
    }
  }

  const XmlElement& named_array(const XmlElement& parent, std::string_view name) const {
    for (const XmlElement& a : parent.children) {
      const std::string* n = a.attribute("Name");
      if (a.name == "DataArray" && n != nullptr && *n == name) return a;
    }
    fail(parent,
         "expected a DataArray Name=\"" + std::string(name) + "\" in <" + parent.name + ">");
  }

  void read_piece(const XmlElement& piece, RawMesh* mesh) {
    const long long num_points = count_attribute(piece, "NumberOfPoints");
    const long long num_cells = count_attribute(piece, "NumberOfCells");
    const int first_point = mesh->num_nodes();
    if (first_point + num_points > (1LL << 31) - 1) fail(piece, "too many points");

    const XmlElement* points = piece.child("Points");
    if (points == nullptr) fail(piece, "expected <Points> in <Piece>");
    const XmlElement* coords = points->child("DataArray");
    if (coords == nullptr) fail(*points, "expected a DataArray in <Points>");
    const std::string* components = coords->attribute("NumberOfComponents");
    if (components == nullptr || *components != "3")
      fail(*coords, "expected NumberOfComponents=\"3\" for Points");
    if (num_points > 0)
      read_array(*coords, 3 * static_cast<std::size_t>(num_points), nullptr, &mesh->xyz);

    const XmlElement* cells_element = piece.child("Cells");
    if (cells_element == nullptr) fail(piece, "expected <Cells> in <Piece>");
    VtkCells cells;
    const XmlElement& conn = named_array(*cells_element, "connectivity");
    const XmlElement& offs = named_array(*cells_element, "offsets");
    const XmlElement& types = named_array(*cells_element, "types");
    read_array(offs, static_cast<std::size_t>(num_cells), &cells.offsets, nullptr);
    cells.offsets.insert(cells.offsets.begin(), 0);
    for (long long i = 0; i < num_cells; ++i) {
      if (cells.offsets[static_cast<std::size_t>(i + 1)] <
          cells.offsets[static_cast<std::size_t>(i)]) {
        fail(offs, "cell offsets decrease at cell " + std::to_string(i));
      }
    }
    read_array(conn, static_cast<std::size_t>(cells.offsets.back()), &cells.connectivity, nullptr);
    read_array(types, static_cast<std::size_t>(num_cells), &cells.types, nullptr);

    if (const XmlElement* cell_data = piece.child("CellData")) {
      for (const XmlElement& a : cell_data->children) {
        const std::string* name = a.attribute("Name");
        const std::string* comps = a.attribute("NumberOfComponents");
        if (a.name != "DataArray" || name == nullptr || (comps != nullptr && *comps != "1"))
          continue;
        if (!array_type(a).integral) continue;
        std::vector<long long> values;
        read_array(a, static_cast<std::size_t>(num_cells), &values, nullptr);
        cells.labels.emplace_back(*name, std::move(values));
      }
    }
    const int conn_line = doc_.line_at(conn.offset);
    add_vtk_cells(
        cells, first_point, static_cast<int>(num_points),
        [&](std::size_t) { return source_ + ":" + std::to_string(conn_line); }, mesh);
  }

  std::string_view text_;
  const std::string& source_;
  XmlDocument doc_;
  bool swap_ = false;
  int header_size_ = 4;
  bool zlib_ = false;
};

}  // namespace

RawMesh read_vtu(std::string_view text, const std::string& source, std::string* format) {
  return VtuReader(text, source).read(format);
}

}  // namespace hapstate
