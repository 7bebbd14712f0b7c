// The format readers behind load_mesh. Each parses a whole file already in memory (`text`,
// named `source` in messages) into a RawMesh, resolving node tags to 0-based ids and throwing
// InputError "file:line: ..." for malformed input. Validation happens afterwards, once.
#pragma once

#include "mesh/raw_mesh.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace hapstate {

// Gmsh .msh: versions 1 ($NOD/$ELM), 2.2 and 4.1, ASCII or binary (version from the header).
RawMesh read_msh(std::string_view text, const std::string& source, std::string* format);
RawMesh read_msh1(std::string_view text, const std::string& source);
RawMesh read_msh2(std::string_view text, const std::string& source, std::string* format);
RawMesh read_msh4(std::string_view text, const std::string& source, std::string* format);

// Legacy VTK UNSTRUCTURED_GRID, ASCII or BINARY (big-endian); old CELLS or 5.1 OFFSETS layout.
RawMesh read_vtk_legacy(std::string_view text, const std::string& source, std::string* format);

// VTK XML UnstructuredGrid (.vtu): ascii, base64 binary, appended raw/base64, zlib compression.
RawMesh read_vtu(std::string_view text, const std::string& source, std::string* format);

// Medit ASCII .mesh (Vertices, Tetrahedra, Triangles, Edges with references).
RawMesh read_medit(std::string_view text, const std::string& source);

// TetGen .node + .ele pair; `file` may name either one.
RawMesh read_tetgen(const std::filesystem::path& file);

// Closed triangle surface (.stl ASCII/binary, .obj) tetrahedralised (fill_closed_surface).
RawMesh read_surface(std::string_view text, const std::string& source, bool obj);

}  // namespace hapstate
