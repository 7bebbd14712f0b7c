#include "io/surface_vtu.h"

#include "util/error.h"

#include <cstdio>
#include <memory>
#include <string>

namespace hapstate {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

void check_sizes(const std::filesystem::path& file, std::span<const float> positions,
                 std::span<const std::int32_t> triangles, std::span<const float> reference) {
  const auto fail = [&](const std::string& what) {
    throw InputError(file.string() + ": cannot write surface VTU: " + what);
  };
  if (positions.size() % 3 != 0) fail("positions are not 3 per vertex");
  if (triangles.size() % 3 != 0) fail("triangles are not 3 indices each");
  if (!reference.empty() && reference.size() != positions.size())
    fail("reference positions do not match the positions");
  const auto vertices = static_cast<std::int64_t>(positions.size() / 3);
  for (std::int32_t v : triangles)
    if (v < 0 || v >= vertices) fail("triangle vertex " + std::to_string(v) + " out of range");
}

}  // namespace

void write_surface_vtu(const std::filesystem::path& file, std::span<const float> positions,
                       std::span<const std::int32_t> triangles, std::span<const float> reference) {
  check_sizes(file, positions, triangles, reference);
  std::unique_ptr<std::FILE, FileCloser> out(std::fopen(file.c_str(), "w"));
  if (!out) throw InputError(file.string() + ": cannot write VTU file");
  std::FILE* f = out.get();
  const std::size_t n = positions.size() / 3;
  const std::size_t m = triangles.size() / 3;
  std::fprintf(
      f,
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n<Points>\n"
      "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n",
      n, m);
  const std::span<const float> points = reference.empty() ? positions : reference;
  for (std::size_t i = 0; i < n; ++i)
    std::fprintf(f, "%.9g %.9g %.9g\n", points[3 * i], points[3 * i + 1], points[3 * i + 2]);
  std::fprintf(f,
               "</DataArray>\n</Points>\n<Cells>\n"
               "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
  for (std::size_t t = 0; t < m; ++t)
    std::fprintf(f, "%d %d %d\n", triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
  std::fprintf(f, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
  for (std::size_t t = 0; t < m; ++t) std::fprintf(f, "%zu\n", 3 * (t + 1));
  std::fprintf(f, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (std::size_t t = 0; t < m; ++t) std::fputs("5\n", f);  // VTK_TRIANGLE
  std::fputs("</DataArray>\n</Cells>\n", f);
  if (!reference.empty()) {
    std::fputs(
        "<PointData Vectors=\"displacement\">\n<DataArray type=\"Float32\" "
        "Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n",
        f);
    for (std::size_t i = 0; i < n; ++i)
      std::fprintf(f, "%.9g %.9g %.9g\n", positions[3 * i] - reference[3 * i],
                   positions[3 * i + 1] - reference[3 * i + 1],
                   positions[3 * i + 2] - reference[3 * i + 2]);
    std::fputs("</DataArray>\n</PointData>\n", f);
  }
  std::fputs("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n", f);
  if (std::ferror(f) || std::fclose(out.release()) != 0)
    throw InputError(file.string() + ": write failed");
}

}  // namespace hapstate
