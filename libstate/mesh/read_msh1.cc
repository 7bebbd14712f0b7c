// Gmsh legacy format 1: $NOD n / id x y z / $ENDNOD, $ELM m / id type phys elem nnodes nodes /
// $ENDELM.
#include "mesh/gmsh_common.h"
#include "mesh/readers.h"

#include <algorithm>

namespace hapstate {

RawMesh read_msh1(std::string_view text, const std::string& source) {
  TextCursor c(text, source);
  RawMesh mesh;
  mesh.source = source;
  NodeTags tags;
  GmshGroups groups;
  bool have_nodes = false;
  bool have_elements = false;
  while (!c.at_end()) {
    const std::string_view section = c.token("section keyword");
    if (section == "$NOD" || section == "$NOE") {
      if (have_nodes) c.fail("second $NOD section (expected one)");
      have_nodes = true;
      const long long n = c.read_int("number of nodes");
      if (n < 0 || n > (1LL << 31) - 1) c.fail("expected a non-negative number of nodes");
      mesh.xyz.reserve(3 * std::min(static_cast<std::size_t>(n), c.capacity(8)));  // >= 4 numbers
      for (long long i = 0; i < n; ++i) {
        const std::string_view t = c.token("node id");
        long long tag = 0;
        if (!parse_int(t, &tag)) {
          c.fail_expected("node id (node " + std::to_string(i + 1) + " of " + std::to_string(n) +
                              " declared by $NOD; wrong node count?)",
                          t);
        }
        if (!tags.add(tag, static_cast<int>(i))) c.fail("duplicate node id " + std::to_string(tag));
        for (int k = 0; k < 3; ++k) mesh.xyz.push_back(c.read_double("node coordinate"));
      }
      const std::string_view end = c.token("$ENDNOD");
      if (end != "$ENDNOD" && end != "$ENDNOE") {
        c.fail_expected("'$ENDNOD' after " + std::to_string(n) + " nodes (wrong node count?)", end);
      }
    } else if (section == "$ELM") {
      if (have_elements) c.fail("second $ELM section (expected one)");
      have_elements = true;
      const long long m = c.read_int("number of elements");
      if (m < 0) c.fail("expected a non-negative number of elements");
      int ids[128];
      for (long long e = 0; e < m; ++e) {
        const std::string_view t = c.token("element id");
        long long id = 0;
        if (!parse_int(t, &id)) {
          c.fail_expected("element id (element " + std::to_string(e + 1) + " of " +
                              std::to_string(m) + " declared by $ELM; wrong element count?)",
                          t);
        }
        const int type = static_cast<int>(c.read_int("element type"));
        const GmshElementType& info = gmsh_element_type(type, c);
        const int phys = static_cast<int>(c.read_int("physical region"));
        c.read_int("elementary region");
        const long long nn = c.read_int("number of element nodes");
        if (nn != info.nodes) {
          c.fail("expected " + std::to_string(info.nodes) + " nodes for element type " +
                 std::to_string(type) + " (" + info.name + "), got " + std::to_string(nn));
        }
        for (int k = 0; k < info.nodes; ++k)
          ids[k] = resolve_gmsh_node(tags, c.read_int("node id"), id, c);
        add_gmsh_element(&mesh, &groups, c, type, ids, &phys, 1);
      }
      const std::string_view end = c.token("$ENDELM");
      if (end != "$ENDELM")
        c.fail_expected("'$ENDELM' after " + std::to_string(m) + " elements (wrong element count?)",
                        end);
    } else {
      c.fail_expected("'$NOD' or '$ELM' (Gmsh format 1 section)", section);
    }
  }
  if (!have_nodes) c.fail("truncated file: no $NOD section");
  if (!have_elements) c.fail("truncated file: no $ELM section");
  name_gmsh_groups({}, std::move(groups), &mesh);
  return mesh;
}

}  // namespace hapstate
