// Medit ASCII .mesh (INRIA / MMG / Tetgen -g): Vertices, Tetrahedra, Triangles, Edges and
// Quadrilaterals with references. Element references r != 0 become groups "ref:r"; vertex
// references are ignored. Indices are 1-based. '#' starts a comment.
#include "mesh/readers.h"
#include "mesh/text_cursor.h"

#include <algorithm>
#include <vector>

namespace hapstate {
namespace {

struct MeditElement {
  const char* keyword;
  int nodes;
  bool tet;
};

// Element sections with their node counts (each line: nodes, then the reference).
constexpr MeditElement kElements[] = {{"Tetrahedra", 4, true},
                                      {"Triangles", 3, false},
                                      {"Edges", 2, false},
                                      {"Quadrilaterals", 4, false}};

// Sections skipped: keyword and numbers per entry.
constexpr std::pair<const char*, int> kSkipped[] = {{"Corners", 1},
                                                    {"RequiredVertices", 1},
                                                    {"Ridges", 1},
                                                    {"RequiredEdges", 1},
                                                    {"RequiredTriangles", 1},
                                                    {"RequiredQuadrilaterals", 1},
                                                    {"RequiredTetrahedra", 1},
                                                    {"Normals", 3},
                                                    {"Tangents", 3},
                                                    {"NormalAtVertices", 2},
                                                    {"TangentAtVertices", 2},
                                                    {"NormalAtTriangleVertices", 3},
                                                    {"Identifier", 0},
                                                    {"Geometry", 0}};

constexpr const char* kUnsupported[] = {"Hexahedra",        "Prisms",      "Pyramids",
                                        "TetrahedraP2",     "TrianglesP2", "EdgesP2",
                                        "QuadrilateralsQ2", "HexahedraQ2"};

long long read_count(TextCursor& c, std::string_view keyword) {
  const long long n = c.read_int(std::string("number of ") + std::string(keyword));
  if (n < 0 || n > (1LL << 31) - 1)
    c.fail("expected a non-negative number of " + std::string(keyword));
  return n;
}

}  // namespace

RawMesh read_medit(std::string_view text, const std::string& source) {
  TextCursor c(text, source, '#');
  RawMesh mesh;
  mesh.source = source;
  std::string_view first = c.token("MeshVersionFormatted");
  if (first != "MeshVersionFormatted")
    c.fail_expected("'MeshVersionFormatted' (Medit .mesh header)", first);
  const long long version = c.read_int("mesh version");
  if (version < 1 || version > 4)
    c.fail("expected MeshVersionFormatted 1..4, got " + std::to_string(version));
  bool have_vertices = false;
  std::vector<int> ids(8);
  while (!c.at_end()) {
    const std::string_view keyword = c.token("section keyword");
    if (keyword == "End") break;
    if (keyword == "Dimension") {
      const long long dim = c.read_int("dimension");
      if (dim != 3) c.fail("expected Dimension 3, got " + std::to_string(dim));
      continue;
    }
    if (keyword == "Vertices") {
      if (have_vertices) c.fail("second Vertices section (expected one)");
      have_vertices = true;
      const long long n = read_count(c, keyword);
      mesh.xyz.reserve(3 * std::min(static_cast<std::size_t>(n), c.capacity(8)));  // >= 4 numbers
      for (long long i = 0; i < n; ++i) {
        const std::string_view t = c.token("vertex x coordinate");
        double x = 0;
        if (!parse_double(t, &x)) {
          c.fail_expected("vertex x coordinate (a finite number; vertex " + std::to_string(i + 1) +
                              " of " + std::to_string(n) + ", wrong vertex count?)",
                          t);
        }
        mesh.xyz.push_back(x);
        mesh.xyz.push_back(c.read_double("vertex y coordinate"));
        mesh.xyz.push_back(c.read_double("vertex z coordinate"));
        c.read_int("vertex reference");
      }
      continue;
    }
    bool handled = false;
    for (const MeditElement& e : kElements) {
      if (keyword != e.keyword) continue;
      handled = true;
      const long long n = read_count(c, keyword);
      for (long long i = 0; i < n; ++i) {
        for (int k = 0; k < e.nodes; ++k) {
          const long long v = c.read_int(std::string(e.keyword) + " vertex index");
          if (v < 1 || v > mesh.num_nodes()) {
            c.fail(std::string(e.keyword) + " element " + std::to_string(i + 1) +
                   " references vertex " + std::to_string(v) + ", but " +
                   std::to_string(mesh.num_nodes()) +
                   " vertices are defined (1-based; missing node)");
          }
          ids[k] = static_cast<int>(v - 1);
        }
        const long long ref = c.read_int("element reference");
        if (e.tet) mesh.tets.push_back({ids[0], ids[1], ids[2], ids[3]});
        if (ref != 0) mesh.add_to_group("ref:" + std::to_string(ref), ids.data(), e.nodes);
      }
    }
    for (const auto& [name, numbers] : kSkipped) {
      if (handled || keyword != name) continue;
      handled = true;
      if (numbers == 0) {
        c.rest_of_line();
        continue;
      }
      const long long n = read_count(c, keyword);
      for (long long i = 0; i < n * numbers; ++i) c.read_double("value");
    }
    for (const char* name : kUnsupported) {
      if (!handled && keyword == name) {
        c.fail("unsupported element section '" + std::string(keyword) +
               "'; only linear tetrahedra (Tetrahedra) are supported as volume elements");
      }
    }
    if (!handled) {
      c.fail_expected("a Medit keyword (Vertices, Tetrahedra, Triangles, Edges, ..., End)",
                      keyword);
    }
  }
  if (!have_vertices) c.fail("truncated file: no Vertices section");
  return mesh;
}

}  // namespace hapstate
