#include "io/vtu_writer.h"

#include "util/error.h"

#include <fstream>
#include <iomanip>

namespace hapstate {

void write_vtu(const std::filesystem::path& file, const Mesh& mesh, const Eigen::Matrix3Xd& u) {
  std::ofstream out(file);
  if (!out) throw InputError(file.string() + ": cannot write VTU file");
  out << std::setprecision(9);
  const int n = mesh.num_nodes();
  const int m = mesh.num_tets();
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << m
      << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (int i = 0; i < n; ++i)
    out << mesh.nodes(0, i) << ' ' << mesh.nodes(1, i) << ' ' << mesh.nodes(2, i) << '\n';
  out << "</DataArray>\n</Points>\n<Cells>\n"
      << "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (int e = 0; e < m; ++e)
    out << mesh.tets(0, e) << ' ' << mesh.tets(1, e) << ' ' << mesh.tets(2, e) << ' '
        << mesh.tets(3, e) << '\n';
  out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (int e = 0; e < m; ++e) out << 4 * (e + 1) << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (int e = 0; e < m; ++e) out << "10\n";
  out << "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n"
      << "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" "
         "format=\"ascii\">\n";
  for (int i = 0; i < n; ++i) out << u(0, i) << ' ' << u(1, i) << ' ' << u(2, i) << '\n';
  out << "</DataArray>\n</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  if (!out) throw InputError(file.string() + ": write failed");
}

void write_pvd(const std::filesystem::path& file,
               const std::vector<std::pair<double, std::string>>& steps) {
  std::ofstream out(file);
  if (!out) throw InputError(file.string() + ": cannot write PVD file");
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& [time, name] : steps)
    out << "<DataSet timestep=\"" << time << "\" file=\"" << name << "\"/>\n";
  out << "</Collection>\n</VTKFile>\n";
}

}  // namespace hapstate
