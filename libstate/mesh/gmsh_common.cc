#include "mesh/gmsh_common.h"

#include "mesh/binary.h"

#include <array>
#include <cstdint>

namespace hapstate {
namespace {

constexpr GmshRole kT = GmshRole::kTet;
constexpr GmshRole kG = GmshRole::kGroupOnly;
constexpr GmshRole kU = GmshRole::kUnsupported;

// Gmsh element types 1..31 (index = type); see the Gmsh reference manual, "MSH file format".
constexpr std::array<GmshElementType, 32> kTypes = {{
    {0, 0, kU, ""},
    {2, 1, kG, "2-node line"},
    {3, 2, kG, "3-node triangle"},
    {4, 2, kG, "4-node quadrangle"},
    {4, 3, kT, "4-node tetrahedron"},
    {8, 3, kU, "8-node hexahedron"},
    {6, 3, kU, "6-node prism"},
    {5, 3, kU, "5-node pyramid"},
    {3, 1, kG, "3-node line"},
    {6, 2, kG, "6-node triangle"},
    {9, 2, kG, "9-node quadrangle"},
    {10, 3, kU, "10-node tetrahedron (higher order)"},
    {27, 3, kU, "27-node hexahedron"},
    {18, 3, kU, "18-node prism"},
    {14, 3, kU, "14-node pyramid"},
    {1, 0, kG, "1-node point"},
    {8, 2, kG, "8-node quadrangle"},
    {20, 3, kU, "20-node hexahedron"},
    {15, 3, kU, "15-node prism"},
    {13, 3, kU, "13-node pyramid"},
    {9, 2, kG, "9-node triangle"},
    {10, 2, kG, "10-node triangle"},
    {12, 2, kG, "12-node triangle"},
    {15, 2, kG, "15-node triangle"},
    {15, 2, kG, "15-node triangle (incomplete)"},
    {21, 2, kG, "21-node triangle"},
    {4, 1, kG, "4-node line"},
    {5, 1, kG, "5-node line"},
    {6, 1, kG, "6-node line"},
    {20, 3, kU, "20-node tetrahedron (higher order)"},
    {35, 3, kU, "35-node tetrahedron (higher order)"},
    {56, 3, kU, "56-node tetrahedron (higher order)"},
}};
constexpr GmshElementType kHex64 = {64, 3, kU, "64-node hexahedron"};
constexpr GmshElementType kHex125 = {125, 3, kU, "125-node hexahedron"};

}  // namespace

const GmshElementType& gmsh_element_type(int type, const TextCursor& cursor) {
  if (type >= 1 && type < static_cast<int>(kTypes.size()))
    return kTypes[static_cast<std::size_t>(type)];
  if (type == 92) return kHex64;
  if (type == 93) return kHex125;
  cursor.fail("unknown Gmsh element type " + std::to_string(type) +
              " (expected a Gmsh element type number such as 4 for a 4-node tetrahedron)");
}

void read_physical_names(TextCursor& cursor, PhysicalNames* names) {
  const long long count = cursor.read_int("number of physical names");
  if (count < 0) cursor.fail("expected a non-negative number of physical names");
  for (long long i = 0; i < count; ++i) {
    const int dim = static_cast<int>(cursor.read_int("physical name dimension"));
    const int tag = static_cast<int>(cursor.read_int("physical tag"));
    std::string_view name = cursor.rest_of_line();
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
      name = name.substr(1, name.size() - 2);
    if (name.empty()) cursor.fail("expected a quoted physical name after dimension and tag");
    (*names)[{dim, tag}] = std::string(name);
  }
  cursor.expect("$EndPhysicalNames");
}

std::string physical_group_name(const PhysicalNames& names, int dim, int tag) {
  const auto it = names.find({dim, tag});
  return it != names.end() ? it->second : std::to_string(tag);
}

void add_gmsh_element(RawMesh* mesh, GmshGroups* groups, const TextCursor& cursor, int type,
                      const int* ids, const int* phys, int num_phys) {
  const GmshElementType& t = gmsh_element_type(type, cursor);
  if (t.role == GmshRole::kUnsupported) {
    cursor.fail(std::string("unsupported element type ") + std::to_string(type) + " (" + t.name +
                "); only linear 4-node tetrahedra (type 4) are supported as volume elements");
  }
  if (t.role == GmshRole::kTet) mesh->tets.push_back({ids[0], ids[1], ids[2], ids[3]});
  for (int i = 0; i < num_phys; ++i) {
    if (phys[i] == 0) continue;  // 0 = no physical group (MSH 1/2)
    auto& g = (*groups)[{t.dim, phys[i]}];
    g.insert(g.end(), ids, ids + t.nodes);
  }
}

void name_gmsh_groups(const PhysicalNames& names, GmshGroups&& groups, RawMesh* mesh) {
  for (auto& [key, ids] : groups)
    mesh->add_to_group(physical_group_name(names, key.first, key.second), ids.data(),
                       static_cast<int>(ids.size()));
}

int resolve_gmsh_node(const NodeTags& tags, long long tag, long long element,
                      const TextCursor& cursor) {
  const int id = tags.find(tag);
  if (id < 0) {
    cursor.fail("element " + std::to_string(element) + " references node tag " +
                std::to_string(tag) + ", which the nodes section does not define (missing node)");
  }
  return id;
}

bool read_gmsh_format_tail(TextCursor& c, int expected_size, bool* swap) {
  const long long file_type = c.read_int("file-type (0 = ASCII, 1 = binary)");
  if (file_type != 0 && file_type != 1)
    c.fail("expected file-type 0 (ASCII) or 1 (binary), got " + std::to_string(file_type));
  const long long data_size = c.read_int("data-size");
  if (data_size != expected_size) {
    c.fail("expected data-size " + std::to_string(expected_size) + ", got " +
           std::to_string(data_size));
  }
  *swap = false;
  if (file_type == 1) {
    c.skip_line_end();
    const char* p = c.take_bytes(4, "endianness marker");
    if (load_binary<std::int32_t>(p, false) == 1) {
      *swap = false;
    } else if (load_binary<std::int32_t>(p, true) == 1) {
      *swap = true;
    } else {
      c.fail("expected the binary integer 1 (endianness marker) after the MSH header");
    }
  }
  c.expect("$EndMeshFormat");
  return file_type == 1;
}

void skip_gmsh_section(TextCursor& cursor, std::string_view keyword) {
  std::string end = "$End" + std::string(keyword.substr(1));
  cursor.skip_past(end);
}

void expect_gmsh_end_elements(TextCursor& cursor, long long count) {
  const std::string_view end = cursor.token("$EndElements");
  if (end != "$EndElements") {
    cursor.fail_expected(
        "'$EndElements' after " + std::to_string(count) + " elements (wrong element count?)", end);
  }
}

void skip_other_gmsh_section(TextCursor& cursor, std::string_view token) {
  if (token.size() > 1 && token.front() == '$') {
    skip_gmsh_section(cursor, token);
  } else {
    cursor.fail_expected("a section keyword such as '$Nodes' or '$Elements'", token);
  }
}

void expect_gmsh_sections_read(const TextCursor& cursor, bool have_nodes, bool have_elements) {
  if (!have_nodes) cursor.fail("truncated file: no $Nodes section");
  if (!have_elements) cursor.fail("truncated file: no $Elements section");
}

}  // namespace hapstate
