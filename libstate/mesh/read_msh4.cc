// Gmsh MSH 4.1, ASCII and binary: $MeshFormat, $PhysicalNames, $Entities, $Nodes, $Elements
// (other sections are skipped). Element blocks of entity tag 0 or without $Entities carry no
// physical groups.
#include "mesh/binary.h"
#include "mesh/gmsh_common.h"
#include "mesh/readers.h"

#include <algorithm>

#include <cstdint>

namespace hapstate {
namespace {

// Reads numbers from either an ASCII or a binary MSH 4.1 body.
class Msh4Numbers {
 public:
  Msh4Numbers(TextCursor& c, bool binary, bool swap) : c_(c), binary_(binary), swap_(swap) {}
  long long size(std::string_view what) {
    if (!binary_) {
      const long long v = c_.read_int(what);
      if (v < 0)
        c_.fail("expected a non-negative " + std::string(what) + ", got " + std::to_string(v));
      return v;
    }
    const std::uint64_t v = load_binary<std::uint64_t>(c_.take_bytes(8, what), swap_);
    if (v > (1ULL << 40)) c_.fail("corrupt binary " + std::string(what) + " " + std::to_string(v));
    return static_cast<long long>(v);
  }
  int integer(std::string_view what) {
    if (!binary_) return static_cast<int>(c_.read_int(what));
    return load_binary<std::int32_t>(c_.take_bytes(4, what), swap_);
  }
  double real(std::string_view what) {
    if (!binary_) return c_.read_double(what);
    return load_binary<double>(c_.take_bytes(8, what), swap_);
  }

 private:
  TextCursor& c_;
  bool binary_;
  bool swap_;
};

using Entities = std::map<std::pair<int, int>, std::vector<int>>;  // (dim, tag) -> physical tags

void read_entities(TextCursor& c, Msh4Numbers& num, Entities* entities) {
  long long counts[4];
  for (int d = 0; d < 4; ++d) counts[d] = num.size("number of entities");
  for (int d = 0; d < 4; ++d) {
    for (long long i = 0; i < counts[d]; ++i) {
      const int tag = num.integer("entity tag");
      for (int k = 0; k < (d == 0 ? 3 : 6); ++k) num.real("entity coordinate");
      const long long nphys = num.size("number of physical tags");
      std::vector<int>& phys = (*entities)[{d, tag}];
      for (long long k = 0; k < nphys; ++k) phys.push_back(num.integer("physical tag"));
      if (d > 0) {
        const long long nbound = num.size("number of bounding entities");
        for (long long k = 0; k < nbound; ++k) num.integer("bounding entity tag");
      }
    }
  }
}

}  // namespace

RawMesh read_msh4(std::string_view text, const std::string& source, std::string* format) {
  TextCursor c(text, source);
  RawMesh mesh;
  mesh.source = source;
  c.expect("$MeshFormat");
  c.token("MSH version");
  bool swap = false;
  const bool binary = read_gmsh_format_tail(c, 8, &swap);
  *format = binary ? "gmsh-4.1-binary" : "gmsh-4.1";
  Msh4Numbers num(c, binary, swap);

  NodeTags tags;
  GmshGroups groups;
  PhysicalNames names;
  Entities entities;
  bool have_entities = false;
  bool have_nodes = false;
  bool have_elements = false;
  std::vector<long long> block_tags;
  std::vector<int> ids(128);
  static const std::vector<int> kNoPhys;
  while (!c.at_end()) {
    const std::string_view section = c.token("section keyword");
    if (section == "$PhysicalNames") {
      read_physical_names(c, &names);
    } else if (section == "$Entities") {
      if (binary) c.skip_line_end();
      read_entities(c, num, &entities);
      have_entities = true;
      c.expect("$EndEntities");
    } else if (section == "$Nodes") {
      if (have_nodes) c.fail("second $Nodes section (expected one)");
      have_nodes = true;
      if (binary) c.skip_line_end();
      const long long blocks = num.size("number of node blocks");
      const int header_line = c.line();
      const long long n = num.size("number of nodes");
      num.size("minimum node tag");
      num.size("maximum node tag");
      if (n > (1LL << 31) - 1) c.fail("too many nodes: " + std::to_string(n));
      mesh.xyz.reserve(3 * std::min(static_cast<std::size_t>(n), c.capacity(8)));  // >= 4 numbers
      long long done = 0;
      for (long long b = 0; b < blocks; ++b) {
        const int dim = num.integer("node block entity dimension");
        num.integer("node block entity tag");
        const int parametric = num.integer("node block parametric flag");
        const long long count = num.size("number of nodes in block");
        if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1)) {
          c.fail("corrupt node block header (dimension " + std::to_string(dim) + ", parametric " +
                 std::to_string(parametric) + ")");
        }
        if (count > n - done) {
          c.fail("node block of " + std::to_string(count) + " nodes exceeds the " +
                 std::to_string(n) + " nodes declared by $Nodes (wrong node count?)");
        }
        if (static_cast<std::size_t>(count) > c.capacity(2)) {
          c.fail("node block of " + std::to_string(count) +
                 " nodes is longer than the rest of the "
                 "file (wrong node count?)");
        }
        block_tags.resize(static_cast<std::size_t>(count));
        for (long long i = 0; i < count; ++i)
          block_tags[static_cast<std::size_t>(i)] = num.size("node tag");
        const int params = parametric != 0 ? dim : 0;
        for (long long i = 0; i < count; ++i) {
          const int id = static_cast<int>(done + i);
          if (!tags.add(block_tags[static_cast<std::size_t>(i)], id)) {
            c.fail("duplicate node tag " + std::to_string(block_tags[static_cast<std::size_t>(i)]));
          }
          for (int k = 0; k < 3; ++k) mesh.xyz.push_back(num.real("node coordinate"));
          for (int k = 0; k < params; ++k) num.real("node parametric coordinate");
        }
        done += count;
      }
      if (done != n) {
        c.fail_at(header_line, "node blocks hold " + std::to_string(done) +
                                   " nodes but $Nodes declares " + std::to_string(n) +
                                   " (wrong node count?)");
      }
      const std::string_view end = c.token("$EndNodes");
      if (end != "$EndNodes")
        c.fail_expected("'$EndNodes' after " + std::to_string(n) + " nodes (wrong node count?)",
                        end);
    } else if (section == "$Elements") {
      if (have_elements) c.fail("second $Elements section (expected one)");
      have_elements = true;
      if (binary) c.skip_line_end();
      const long long blocks = num.size("number of element blocks");
      const int header_line = c.line();
      const long long m = num.size("number of elements");
      num.size("minimum element tag");
      num.size("maximum element tag");
      long long done = 0;
      for (long long b = 0; b < blocks; ++b) {
        const int dim = num.integer("element block entity dimension");
        const int entity = num.integer("element block entity tag");
        const int type = num.integer("element type");
        const long long count = num.size("number of elements in block");
        const GmshElementType& info = gmsh_element_type(type, c);
        if (count > m - done) {
          c.fail("element block of " + std::to_string(count) + " elements exceeds the " +
                 std::to_string(m) + " elements declared by $Elements (wrong element count?)");
        }
        const std::vector<int>* phys = &kNoPhys;
        if (have_entities && entity != 0) {
          const auto it = entities.find({dim, entity});
          if (it == entities.end()) {
            c.fail("element block refers to entity (dimension " + std::to_string(dim) + ", tag " +
                   std::to_string(entity) + "), which $Entities does not define");
          }
          phys = &it->second;
        }
        for (long long e = 0; e < count; ++e) {
          const long long id = num.size("element tag");
          for (int k = 0; k < info.nodes; ++k)
            ids[k] = resolve_gmsh_node(tags, num.size("node tag"), id, c);
          add_gmsh_element(&mesh, &groups, c, type, ids.data(), phys->data(),
                           static_cast<int>(phys->size()));
        }
        done += count;
      }
      if (done != m) {
        c.fail_at(header_line, "element blocks hold " + std::to_string(done) +
                                   " elements but $Elements declares " + std::to_string(m) +
                                   " (wrong element count?)");
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
