// TetGen .node/.ele pair. Indices may start at 0 or 1 (whatever the .node file uses); optional
// node attributes and boundary markers, optional tet attributes. Nonzero node boundary markers
// become groups "marker:m"; an integral first tet attribute (region) becomes "region:r".
#include "mesh/readers.h"
#include "mesh/text_cursor.h"
#include "util/error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(file.string() + ": cannot open TetGen file (a .node/.ele pair is required)");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

RawMesh read_tetgen(const std::filesystem::path& file) {
  std::filesystem::path node_file = file;
  std::filesystem::path ele_file = file;
  node_file.replace_extension(".node");
  ele_file.replace_extension(".ele");
  const std::string node_text = read_text(node_file);
  const std::string ele_text = read_text(ele_file);
  RawMesh mesh;
  mesh.source = file.string();
  NodeTags tags;

  TextCursor c(node_text, node_file.string(), '#');
  const long long n = c.read_int("number of points");
  if (n < 0 || n > (1LL << 31) - 1) c.fail("expected a non-negative number of points");
  const long long dim = c.read_int("dimension");
  if (dim != 3) c.fail("expected dimension 3, got " + std::to_string(dim));
  const long long attributes = c.read_int("number of point attributes");
  const long long markers = c.read_int("number of boundary markers (0 or 1)");
  if (attributes < 0 || attributes > 1000 || (markers != 0 && markers != 1)) {
    c.fail("expected point attribute count >= 0 and boundary markers 0 or 1");
  }
  mesh.xyz.reserve(3 * std::min(static_cast<std::size_t>(n), c.capacity(8)));  // >= 4 numbers
  for (long long i = 0; i < n; ++i) {
    const std::string_view t = c.token("point index");
    long long index = 0;
    if (!parse_int(t, &index)) {
      c.fail_expected("point index (point " + std::to_string(i + 1) + " of " + std::to_string(n) +
                          "; wrong point count?)",
                      t);
    }
    if (!tags.add(index, static_cast<int>(i)))
      c.fail("duplicate point index " + std::to_string(index));
    for (int k = 0; k < 3; ++k) mesh.xyz.push_back(c.read_double("point coordinate"));
    for (long long k = 0; k < attributes; ++k) c.read_double("point attribute");
    if (markers == 1) {
      const long long m = c.read_int("boundary marker");
      const int id = static_cast<int>(i);
      if (m != 0) mesh.add_to_group("marker:" + std::to_string(m), &id, 1);
    }
  }
  if (!c.at_end())
    c.fail_expected("end of file after " + std::to_string(n) + " points (wrong point count?)",
                    c.peek());

  TextCursor e(ele_text, ele_file.string(), '#');
  const long long m = e.read_int("number of tetrahedra");
  if (m < 0) e.fail("expected a non-negative number of tetrahedra");
  const long long per_tet = e.read_int("nodes per tetrahedron");
  if (per_tet == 10)
    e.fail("unsupported higher-order tetrahedra (10 nodes per tet); only linear 4-node tets");
  if (per_tet != 4) e.fail("expected 4 nodes per tetrahedron, got " + std::to_string(per_tet));
  const long long tet_attributes = e.read_int("number of tetrahedron attributes");
  if (tet_attributes < 0 || tet_attributes > 1000)
    e.fail("expected a small number of tetrahedron attributes");
  mesh.tets.reserve(std::min(static_cast<std::size_t>(m), e.capacity(10)));  // >= 5 numbers
  for (long long i = 0; i < m; ++i) {
    const std::string_view t = e.token("tetrahedron index");
    long long index = 0;
    if (!parse_int(t, &index)) {
      e.fail_expected("tetrahedron index (tet " + std::to_string(i + 1) + " of " +
                          std::to_string(m) + "; wrong tet count?)",
                      t);
    }
    std::array<int, 4> tet{};
    for (int k = 0; k < 4; ++k) {
      const long long v = e.read_int("node index");
      tet[k] = tags.find(v);
      if (tet[k] < 0) {
        e.fail("tetrahedron " + std::to_string(index) + " references point " + std::to_string(v) +
               ", which " + node_file.filename().string() + " does not define (missing node)");
      }
    }
    mesh.tets.push_back(tet);
    for (long long k = 0; k < tet_attributes; ++k) {
      const double a = e.read_double("tetrahedron attribute");
      if (k == 0 && a == std::floor(a) && std::abs(a) < 1e9) {
        mesh.add_to_group("region:" + std::to_string(static_cast<long long>(a)), tet.data(), 4);
      }
    }
  }
  if (!e.at_end())
    e.fail_expected("end of file after " + std::to_string(m) + " tetrahedra (wrong tet count?)",
                    e.peek());
  return mesh;
}

}  // namespace hapstate
