// load_mesh: reads the file, picks the reader by extension (checked against the content), then
// validates once for every format.
#include "mesh/load.h"

#include "mesh/readers.h"
#include "mesh/validate.h"
#include "util/error.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

std::string read_whole_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open mesh file");
  std::string text;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(file.string() + ": cannot read mesh file");
  text.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  in.read(text.data(), size);
  if (!in) throw InputError(file.string() + ": cannot read mesh file");
  return text;
}

// First non-blank characters of `text` start with `prefix`.
bool starts_with_skipping_space(std::string_view text, std::string_view prefix) {
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])) != 0) ++i;
  return text.substr(i, prefix.size()) == prefix;
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& file, MeshReport* report) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  const std::string source = file.string();
  std::string format;
  RawMesh raw;
  if (ext == ".node" || ext == ".ele") {
    raw = read_tetgen(file);
    format = "tetgen";
  } else {
    static const char* kKnown[] = {".msh", ".vtk", ".vtu", ".mesh", ".stl", ".obj"};
    if (std::find(std::begin(kKnown), std::end(kKnown), ext) == std::end(kKnown)) {
      throw InputError(source + ": unknown mesh format '" + ext +
                       "' (expected .msh, .vtk, .vtu, .mesh, .node/.ele, .stl or .obj)");
    }
    const std::string text = read_whole_file(file);
    if (ext == ".msh") {
      raw = read_msh(text, source, &format);
    } else if (ext == ".vtu" || (ext == ".vtk" && (starts_with_skipping_space(text, "<?xml") ||
                                                   starts_with_skipping_space(text, "<VTKFile")))) {
      raw = read_vtu(text, source, &format);  // some tools write XML under a .vtk name
    } else if (ext == ".vtk") {
      raw = read_vtk_legacy(text, source, &format);
    } else if (ext == ".mesh") {
      raw = read_medit(text, source);
      format = "medit";
    } else {
      raw = read_surface(text, source, ext == ".obj");
      format = ext == ".obj" ? "obj-surface" : "stl-surface";
    }
  }
  Mesh mesh = validate_mesh(std::move(raw), report);
  if (report != nullptr) report->format = format;
  return mesh;
}

}  // namespace hapstate
