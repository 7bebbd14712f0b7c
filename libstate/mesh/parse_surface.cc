// Readers for triangle surfaces: Wavefront OBJ and STL (ASCII and binary).
#include "mesh/binary.h"
#include "mesh/readers.h"
#include "mesh/surface.h"
#include "mesh/text_cursor.h"
#include "util/error.h"

#include <cmath>
#include <cstdint>
#include <map>

namespace hapstate {

TriangleSurface parse_obj(std::string_view text, const std::string& source) {
  TriangleSurface s;
  s.source = source;
  TextCursor c(text, source, '#');
  std::vector<int> polygon;
  while (!c.at_end()) {
    const std::string_view key = c.token("OBJ keyword");
    if (key == "v") {
      for (int k = 0; k < 3; ++k) s.xyz.push_back(c.read_double("vertex coordinate"));
      c.rest_of_line();  // optional w
    } else if (key == "f") {
      const int line = c.line();
      polygon.clear();
      for (std::string_view rest = c.rest_of_line(); !rest.empty();) {
        const std::size_t end = rest.find_first_of(" \t");
        const std::string_view corner = rest.substr(0, end);
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end);
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t'))
          rest.remove_prefix(1);
        long long v = 0;
        if (!parse_int(corner.substr(0, corner.find('/')), &v) || v == 0) {
          c.fail_at(line, "expected a face vertex index (v, v/vt, v//vn or v/vt/vn), got '" +
                              printable(corner) + "'");
        }
        const long long count = static_cast<long long>(s.xyz.size() / 3);
        const long long id = v > 0 ? v - 1 : count + v;  // negative = relative to the end
        if (id < 0 || id >= count) {
          c.fail_at(line, "face references vertex " + std::to_string(v) + ", but only " +
                              std::to_string(count) +
                              " vertices are defined so far (missing node)");
        }
        polygon.push_back(static_cast<int>(id));
      }
      if (polygon.size() < 3) c.fail_at(line, "expected a face with at least 3 vertices");
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        s.faces.push_back({polygon[0], polygon[k], polygon[k + 1]});
        s.face_lines.push_back(line);
      }
    } else {
      c.rest_of_line();  // vn, vt, g, o, s, usemtl, mtllib, l, ...: not needed
    }
  }
  if (s.faces.empty()) c.fail("expected triangle faces ('f' lines) in the OBJ file, found none");
  return s;
}

TriangleSurface parse_stl(std::string_view text, const std::string& source) {
  TriangleSurface s;
  s.source = source;
  std::map<std::array<double, 3>, int> index;
  const auto vertex = [&](const std::array<double, 3>& p) {
    const auto [it, inserted] = index.emplace(p, static_cast<int>(s.xyz.size() / 3));
    if (inserted) s.xyz.insert(s.xyz.end(), p.begin(), p.end());
    return it->second;
  };
  // Binary if the size matches the triangle count (ASCII files may also start with "solid").
  if (text.size() >= 84) {
    const std::uint32_t n = load_binary<std::uint32_t>(text.data() + 80, !kHostLittleEndian);
    if (text.size() == 84 + 50 * static_cast<std::size_t>(n)) {
      for (std::uint32_t t = 0; t < n; ++t) {
        const char* p = text.data() + 84 + 50 * static_cast<std::size_t>(t) + 12;
        std::array<int, 3> face{};
        for (int k = 0; k < 3; ++k) {
          std::array<double, 3> q{};
          for (int j = 0; j < 3; ++j)
            q[j] = load_binary<float>(p + 12 * k + 4 * j, !kHostLittleEndian);
          for (double v : q) {
            if (!std::isfinite(v))
              throw InputError(source + ": binary STL triangle " + std::to_string(t) +
                               " has a non-finite coordinate");
          }
          face[k] = vertex(q);
        }
        s.faces.push_back(face);
        s.face_lines.push_back(0);
      }
      if (s.faces.empty()) throw InputError(source + ": binary STL holds no triangles");
      return s;
    }
  }
  TextCursor c(text, source);
  c.expect("solid");
  c.rest_of_line();
  while (true) {
    const std::string_view key = c.token("'facet' or 'endsolid'");
    if (key == "endsolid") break;
    if (key != "facet")
      c.fail_expected("'facet' or 'endsolid' (or a binary STL of the right size)", key);
    const int line = c.line();
    c.expect("normal");
    for (int k = 0; k < 3; ++k) c.read_double("normal component");
    c.expect("outer");
    c.expect("loop");
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k) {
      c.expect("vertex");
      std::array<double, 3> q{};
      for (int j = 0; j < 3; ++j) q[j] = c.read_double("vertex coordinate");
      face[k] = vertex(q);
    }
    c.expect("endloop");
    c.expect("endfacet");
    s.faces.push_back(face);
    s.face_lines.push_back(line);
  }
  if (s.faces.empty()) c.fail("STL holds no facets");
  return s;
}

RawMesh read_surface(std::string_view text, const std::string& source, bool obj) {
  const TriangleSurface s = obj ? parse_obj(text, source) : parse_stl(text, source);
  return fill_closed_surface(s);
}

}  // namespace hapstate
