// Pieces shared by the Gmsh MSH readers: the element type table, physical names and how an
// element is turned into a tet or into group members.
#pragma once

#include "mesh/raw_mesh.h"
#include "mesh/text_cursor.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hapstate {

// What the importer does with a Gmsh element type.
enum class GmshRole { kTet, kGroupOnly, kUnsupported };

struct GmshElementType {
  int nodes = 0;  // nodes per element
  int dim = 0;    // topological dimension
  GmshRole role = GmshRole::kUnsupported;
  const char* name = "";
};

// Looks up a Gmsh element type number; throws "file:line: unknown Gmsh element type N" (line of
// the last token of `cursor`) if Gmsh does not define it.
const GmshElementType& gmsh_element_type(int type, const TextCursor& cursor);

// (dimension, physical tag) -> name, from $PhysicalNames.
using PhysicalNames = std::map<std::pair<int, int>, std::string>;

// Parses a $PhysicalNames section body (after the keyword line) up to $EndPhysicalNames.
void read_physical_names(TextCursor& cursor, PhysicalNames* names);

// Group name of physical tag `tag` on an element of dimension `dim`: its name if it has one,
// else the number.
std::string physical_group_name(const PhysicalNames& names, int dim, int tag);

// Node ids of the elements of each physical group, keyed by (element dimension, physical tag).
using GmshGroups = std::map<std::pair<int, int>, std::vector<int>>;

// Adds one element with 0-based node ids `ids` and physical tags `phys[0..num_phys)`: a tet for
// type 4; every element's nodes go to its physical groups. Throws a file:line "unsupported
// element type" error for volume elements other than linear tets (hexahedra, tet10, ...).
void add_gmsh_element(RawMesh* mesh, GmshGroups* groups, const TextCursor& cursor, int type,
                      const int* ids, const int* phys, int num_phys);

// Moves `groups` into mesh->groups under their names (physical_group_name).
void name_gmsh_groups(const PhysicalNames& names, GmshGroups&& groups, RawMesh* mesh);

// Reads a node tag reference and returns its 0-based id; throws "file:line: element E
// references node tag T, which $Nodes does not define".
int resolve_gmsh_node(const NodeTags& tags, long long tag, long long element,
                      const TextCursor& cursor);

// Reads the rest of $MeshFormat after the version token (file-type, data-size, the binary
// endianness marker, $EndMeshFormat). Returns true for binary; sets *swap if the file's byte
// order differs from the host's.
bool read_gmsh_format_tail(TextCursor& c, int expected_size, bool* swap);

// Skips an unknown section "$Name" (its keyword already read) to just past "$EndName".
void skip_gmsh_section(TextCursor& cursor, std::string_view keyword);

// Reads the "$EndElements" that must follow the `count` elements of an $Elements section.
void expect_gmsh_end_elements(TextCursor& cursor, long long count);

// A token that is no section the reader knows: skips "$Name ... $EndName", fails for a token
// that is not a section keyword at all.
void skip_other_gmsh_section(TextCursor& cursor, std::string_view token);

// Fails with "truncated file" unless both $Nodes and $Elements were read.
void expect_gmsh_sections_read(const TextCursor& cursor, bool have_nodes, bool have_elements);

}  // namespace hapstate
