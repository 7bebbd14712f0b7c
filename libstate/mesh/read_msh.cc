// Gmsh .msh: picks the reader for the version in the header.
#include "mesh/readers.h"
#include "mesh/text_cursor.h"

namespace hapstate {

RawMesh read_msh(std::string_view text, const std::string& source, std::string* format) {
  TextCursor c(text, source);
  const std::string_view first = c.token("'$MeshFormat' or '$NOD' (Gmsh file)");
  if (first == "$NOD" || first == "$NOE") {
    *format = "gmsh-1";
    return read_msh1(text, source);
  }
  if (first != "$MeshFormat") c.fail_expected("'$MeshFormat' or '$NOD' (Gmsh MSH file)", first);
  const std::string_view version = c.token("MSH version");
  if (version == "2" || version == "2.0" || version == "2.1" || version == "2.2")
    return read_msh2(text, source, format);
  if (version == "4.1") return read_msh4(text, source, format);
  c.fail("unsupported MSH version '" + printable(version) +
         "' (expected 1, 2.2 or 4.1; re-save with Gmsh: File > Export, 'Version 4 ASCII' or 2.2)");
}

}  // namespace hapstate
