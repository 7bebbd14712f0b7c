#include "mesh/readers.h"
#include <stdexcept>
namespace hapstate {
RawMesh read_vtu(std::string_view, const std::string&, std::string*) { throw std::runtime_error("todo"); }
RawMesh read_medit(std::string_view, const std::string&) { throw std::runtime_error("todo"); }
RawMesh read_tetgen(const std::filesystem::path&) { throw std::runtime_error("todo"); }
RawMesh read_surface(std::string_view, const std::string&, bool) { throw std::runtime_error("todo"); }
}
