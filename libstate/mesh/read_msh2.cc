// Gmsh MSH 2.2, ASCII and binary: $MeshFormat, $PhysicalNames, $Nodes, $Elements (other sections
// are skipped).
#include "mesh/binary.h"
#include "mesh/gmsh_common.h"
#include "mesh/readers.h"

#include <algorithm>

#include <cstdint>

namespace hapstate {

RawMesh read_msh2(std::string_view text, const std::string& source, std::string* format) {
  TextCursor c(text, source);
  RawMesh mesh;
  mesh.source = source;
  c.expect("$MeshFormat");
  c.token("MSH version");
  bool swap = false;
  const bool binary = read_gmsh_format_tail(c, 8, &swap);
  *format = binary ? "gmsh-2.2-binary" : "gmsh-2.2";

  NodeTags tags;
  GmshGroups groups;
  PhysicalNames names;
  bool have_nodes = false;
  bool have_elements = false;
  std::vector<int> ids(128);
  std::vector<int> phys;
  while (!c.at_end()) {
    const std::string_view section = c.token("section keyword");
    if (section == "$PhysicalNames") {
      read_physical_names(c, &names);
    } else if (section == "$Nodes") {
      if (have_nodes) c.fail("second $Nodes section (expected one)");
      have_nodes = true;
      const long long n = c.read_int("number of nodes");
      if (n < 0 || n > (1LL << 31) - 1) c.fail("expected a non-negative number of nodes");
      mesh.xyz.reserve(3 * std::min(static_cast<std::size_t>(n), c.capacity(8)));  // >= 4 numbers
      if (binary) {
        c.skip_line_end();
        const char* p =
            c.take_bytes(static_cast<std::size_t>(n) * 28, "nodes (int id + 3 doubles each)");
        for (long long i = 0; i < n; ++i, p += 28) {
          const long long tag = load_binary<std::int32_t>(p, swap);
          if (!tags.add(tag, static_cast<int>(i)))
            c.fail("duplicate node id " + std::to_string(tag) + " in binary $Nodes");
          for (int k = 0; k < 3; ++k) mesh.xyz.push_back(load_binary<double>(p + 4 + 8 * k, swap));
        }
      } else {
        for (long long i = 0; i < n; ++i) {
          const std::string_view t = c.token("node id");
          long long tag = 0;
          if (!parse_int(t, &tag)) {
            c.fail_expected("node id (node " + std::to_string(i + 1) + " of " + std::to_string(n) +
                                " declared by $Nodes; wrong node count?)",
                            t);
          }
          if (!tags.add(tag, static_cast<int>(i)))
            c.fail("duplicate node id " + std::to_string(tag));
          for (int k = 0; k < 3; ++k) mesh.xyz.push_back(c.read_double("node coordinate"));
        }
      }
      const std::string_view end = c.token("$EndNodes");
      if (end != "$EndNodes")
        c.fail_expected("'$EndNodes' after " + std::to_string(n) + " nodes (wrong node count?)",
                        end);
    } else if (section == "$Elements") {
      if (have_elements) c.fail("second $Elements section (expected one)");
      have_elements = true;
      const long long m = c.read_int("number of elements");
      if (m < 0) c.fail("expected a non-negative number of elements");
      if (binary) {
        c.skip_line_end();
        long long done = 0;
        while (done < m) {
          const char* h = c.take_bytes(12, "element block header (type, count, number of tags)");
          const int type = load_binary<std::int32_t>(h, swap);
          const long long count = load_binary<std::int32_t>(h + 4, swap);
          const int ntags = load_binary<std::int32_t>(h + 8, swap);
          const GmshElementType& info = gmsh_element_type(type, c);
          if (count <= 0 || count > m - done || ntags < 0 || ntags > 64) {
            c.fail("corrupt binary element block header (type " + std::to_string(type) +
                   ", count " + std::to_string(count) + ", tags " + std::to_string(ntags) + ")");
          }
          const std::size_t stride = 4 * static_cast<std::size_t>(1 + ntags + info.nodes);
          const char* p = c.take_bytes(stride * static_cast<std::size_t>(count), "elements");
          phys.assign(ntags > 0 ? 1 : 0, 0);
          for (long long e = 0; e < count; ++e, p += stride) {
            const long long id = load_binary<std::int32_t>(p, swap);
            if (ntags > 0) phys[0] = load_binary<std::int32_t>(p + 4, swap);
            for (int k = 0; k < info.nodes; ++k) {
              ids[k] = resolve_gmsh_node(
                  tags, load_binary<std::int32_t>(p + 4 * (1 + ntags + k), swap), id, c);
            }
            add_gmsh_element(&mesh, &groups, c, type, ids.data(), phys.data(),
                             static_cast<int>(phys.size()));
          }
          done += count;
        }
      } else {
        for (long long e = 0; e < m; ++e) {
          const std::string_view t = c.token("element id");
          long long id = 0;
          if (!parse_int(t, &id)) {
            c.fail_expected("element id (element " + std::to_string(e + 1) + " of " +
                                std::to_string(m) + " declared by $Elements; wrong element count?)",
                            t);
          }
          const int type = static_cast<int>(c.read_int("element type"));
          const GmshElementType& info = gmsh_element_type(type, c);
          const long long ntags = c.read_int("number of tags");
          if (ntags < 0 || ntags > 64)
            c.fail("expected a small number of tags, got " + std::to_string(ntags));
          phys.clear();
          for (long long k = 0; k < ntags; ++k) {
            const int tag = static_cast<int>(c.read_int("element tag"));
            if (k == 0) phys.push_back(tag);
          }
          for (int k = 0; k < info.nodes; ++k)
            ids[k] = resolve_gmsh_node(tags, c.read_int("node id"), id, c);
          add_gmsh_element(&mesh, &groups, c, type, ids.data(), phys.data(),
                           static_cast<int>(phys.size()));
        }
      }
      expect_gmsh_end_elements(c, m);
    } else {
      skip_other_gmsh_section(c, section);
    }
  }
  expect_gmsh_sections_read(c, have_nodes, have_elements);
  name_gmsh_groups(names, std::move(groups), &mesh);
  return mesh;
}

}  // namespace hapstate
