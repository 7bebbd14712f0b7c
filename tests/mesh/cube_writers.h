// Writers of the test cube (mesh_test_util.h) in every supported format, kept tiny and
// independent of the library readers. Node tags are written sparse and out of order where a
// format allows it, so the readers' tag mapping is exercised.
#pragma once

#include "mesh_test_util.h"

#include <zlib.h>
#include <sstream>

namespace hapstate::test {

// Gmsh tag of cube node i (sparse, descending).
inline int gmsh_tag(int i) { return 100 - 10 * i; }

inline std::string msh1(const CubeMesh& c) {
  std::ostringstream s;
  s.precision(17);
  s << "$NOD\n" << c.nodes.size() << "\n";
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    s << gmsh_tag(int(i)) << " " << c.nodes[i][0] << " " << c.nodes[i][1] << " " << c.nodes[i][2]
      << "\n";
  }
  s << "$ENDNOD\n$ELM\n" << c.tets.size() + c.bottom.size() << "\n";
  int id = 1;
  for (const auto& t : c.bottom)
    s << id++ << " 2 7 1 3 " << gmsh_tag(t[0]) << " " << gmsh_tag(t[1]) << " " << gmsh_tag(t[2])
      << "\n";
  for (const auto& t : c.tets) {
    s << id++ << " 4 9 1 4";
    for (int v : t) s << " " << gmsh_tag(v);
    s << "\n";
  }
  s << "$ENDELM\n";
  return s.str();
}

inline std::string msh2(const CubeMesh& c, bool binary) {
  std::string s = binary ? "$MeshFormat\n2.2 1 8\n" : "$MeshFormat\n2.2 0 8\n";
  if (binary) {
    put<std::int32_t>(&s, 1);
    s += "\n";
  }
  s += "$EndMeshFormat\n$PhysicalNames\n2\n2 7 \"bottom\"\n3 9 \"body\"\n$EndPhysicalNames\n";
  s += "$Nodes\n" + std::to_string(c.nodes.size()) + "\n";
  std::ostringstream a;
  a.precision(17);
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    if (binary) {
      put<std::int32_t>(&s, gmsh_tag(int(i)));
      for (double x : c.nodes[i]) put<double>(&s, x);
    } else {
      a.str("");
      a << gmsh_tag(int(i)) << " " << c.nodes[i][0] << " " << c.nodes[i][1] << " " << c.nodes[i][2]
        << "\n";
      s += a.str();
    }
  }
  s += binary ? "\n$EndNodes\n" : "$EndNodes\n";
  s += "$Elements\n" + std::to_string(c.tets.size() + c.bottom.size()) + "\n";
  int id = 1;
  if (binary) {
    for (int type : {2, 4}) {
      put<std::int32_t>(&s, type);
      put<std::int32_t>(&s, type == 2 ? int(c.bottom.size()) : int(c.tets.size()));
      put<std::int32_t>(&s, 2);
      if (type == 2) {
        for (const auto& t : c.bottom) {
          for (int v : {id++, 7, 1}) put<std::int32_t>(&s, v);
          for (int v : t) put<std::int32_t>(&s, gmsh_tag(v));
        }
      } else {
        for (const auto& t : c.tets) {
          for (int v : {id++, 9, 1}) put<std::int32_t>(&s, v);
          for (int v : t) put<std::int32_t>(&s, gmsh_tag(v));
        }
      }
    }
    s += "\n";
  } else {
    for (const auto& t : c.bottom) {
      s += std::to_string(id++) + " 2 2 7 1";
      for (int v : t) s.append(1, ' ').append(std::to_string(gmsh_tag(v)));
      s += "\n";
    }
    for (const auto& t : c.tets) {
      s += std::to_string(id++) + " 4 2 9 1";
      for (int v : t) s.append(1, ' ').append(std::to_string(gmsh_tag(v)));
      s += "\n";
    }
  }
  s += "$EndElements\n";
  return s;
}

// MSH 4.1 with $Entities: surface 1 (physical 7 "bottom"), volume 1 (physical 9 "body"); nodes
// in two blocks.
inline std::string msh4(const CubeMesh& c, bool binary) {
  std::string s = binary ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n";
  if (binary) {
    put<std::int32_t>(&s, 1);
    s += "\n";
  }
  s += "$EndMeshFormat\n$PhysicalNames\n2\n2 7 \"bottom\"\n3 9 "
       "\"body\"\n$EndPhysicalNames\n$Entities\n";
  std::ostringstream a;
  a.precision(17);
  if (binary) {
    for (std::uint64_t n : {0, 0, 1, 1}) put<std::uint64_t>(&s, n);
    for (int dim = 2; dim <= 3; ++dim) {
      put<std::int32_t>(&s, 1);
      for (double x : {0., 0., 0., 1., 1., 1.}) put<double>(&s, x);
      put<std::uint64_t>(&s, 1);
      put<std::int32_t>(&s, dim == 2 ? 7 : 9);
      put<std::uint64_t>(&s, dim == 2 ? 0 : 1);
      if (dim == 3) put<std::int32_t>(&s, 1);
    }
    s += "\n";
  } else {
    s += "0 0 1 1\n1 0 0 0 1 1 1 1 7 0\n1 0 0 0 1 1 1 1 9 1 1\n";
  }
  s += "$EndEntities\n$Nodes\n";
  const std::vector<std::vector<int>> blocks = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  if (binary) {
    for (std::uint64_t n : {2, 8, 30, 100}) put<std::uint64_t>(&s, n);
    for (const auto& b : blocks) {
      for (int v : {3, 1, 0}) put<std::int32_t>(&s, v);
      put<std::uint64_t>(&s, b.size());
      for (int i : b) put<std::uint64_t>(&s, std::uint64_t(gmsh_tag(i)));
      for (int i : b) {
        for (double x : c.nodes[i]) put<double>(&s, x);
      }
    }
    s += "\n";
  } else {
    s += "2 8 30 100\n";
    for (const auto& b : blocks) {
      s += "3 1 0 " + std::to_string(b.size()) + "\n";
      for (int i : b) s += std::to_string(gmsh_tag(i)) + "\n";
      for (int i : b) {
        a.str("");
        a << c.nodes[i][0] << " " << c.nodes[i][1] << " " << c.nodes[i][2] << "\n";
        s += a.str();
      }
    }
  }
  s += "$EndNodes\n$Elements\n";
  if (binary) {
    for (std::uint64_t n : {2, 8, 1, 8}) put<std::uint64_t>(&s, n);
    std::uint64_t id = 1;
    for (int type : {2, 4}) {
      for (int v : {type == 2 ? 2 : 3, 1, type}) put<std::int32_t>(&s, v);
      put<std::uint64_t>(&s, type == 2 ? c.bottom.size() : c.tets.size());
      if (type == 2) {
        for (const auto& t : c.bottom) {
          put<std::uint64_t>(&s, id++);
          for (int v : t) put<std::uint64_t>(&s, std::uint64_t(gmsh_tag(v)));
        }
      } else {
        for (const auto& t : c.tets) {
          put<std::uint64_t>(&s, id++);
          for (int v : t) put<std::uint64_t>(&s, std::uint64_t(gmsh_tag(v)));
        }
      }
    }
    s += "\n";
  } else {
    s += "2 8 1 8\n2 1 2 2\n";
    int id = 1;
    for (const auto& t : c.bottom)
      s += std::to_string(id++) + " " + std::to_string(gmsh_tag(t[0])) + " " +
           std::to_string(gmsh_tag(t[1])) + " " + std::to_string(gmsh_tag(t[2])) + "\n";
    s += "3 1 4 6\n";
    for (const auto& t : c.tets) {
      s += std::to_string(id++);
      for (int v : t) s.append(1, ' ').append(std::to_string(gmsh_tag(v)));
      s += "\n";
    }
  }
  s += "$EndElements\n";
  return s;
}

// Legacy VTK: the 6 tets, then the 2 bottom triangles; CELL_DATA int "label" (1 = tet,
// 2 = bottom triangle) as SCALARS, plus a FIELD with a float array (skipped) and an int array.
inline std::string vtk_legacy(const CubeMesh& c, bool binary, bool offsets_layout) {
  std::string s = std::string("# vtk DataFile Version ") + (offsets_layout ? "5.1" : "3.0") +
                  "\ncube\n" + (binary ? "BINARY" : "ASCII") + "\nDATASET UNSTRUCTURED_GRID\n";
  s += "POINTS 8 double\n";
  std::ostringstream a;
  a.precision(17);
  for (const auto& p : c.nodes) {
    if (binary) {
      for (double x : p) put<double>(&s, x, true);
    } else {
      a.str("");
      a << p[0] << " " << p[1] << " " << p[2] << "   ";  // several points per line, trailing spaces
      s += a.str();
    }
  }
  s += "\n";
  std::vector<std::vector<int>> cells;
  for (const auto& t : c.tets) cells.push_back({t[0], t[1], t[2], t[3]});
  for (const auto& t : c.bottom) cells.push_back({t[0], t[1], t[2]});
  if (offsets_layout) {
    std::vector<long long> offsets{0};
    std::vector<long long> conn;
    for (const auto& cell : cells) {
      conn.insert(conn.end(), cell.begin(), cell.end());
      offsets.push_back(static_cast<long long>(conn.size()));
    }
    s += "CELLS " + std::to_string(offsets.size()) + " " + std::to_string(conn.size()) +
         "\nOFFSETS vtktypeint64\n";
    for (long long o : offsets)
      binary ? put<std::int64_t>(&s, o, true) : void(s += std::to_string(o) + "\n");
    s += binary ? "\nCONNECTIVITY vtktypeint64\n" : "CONNECTIVITY vtktypeint64\n";
    for (long long v : conn)
      binary ? put<std::int64_t>(&s, v, true) : void(s += std::to_string(v) + " ");
    s += "\n";
  } else {
    s += "CELLS " + std::to_string(cells.size()) + " " + std::to_string(6 * 5 + 2 * 4) + "\n";
    for (const auto& cell : cells) {
      if (binary) {
        put<std::int32_t>(&s, int(cell.size()), true);
        for (int v : cell) put<std::int32_t>(&s, v, true);
      } else {
        s += std::to_string(cell.size());
        for (int v : cell) s.append(1, ' ').append(std::to_string(v));
        s += "\n";
      }
    }
    if (binary) s += "\n";
  }
  s += "CELL_TYPES 8\n";
  for (const auto& cell : cells)
    binary ? put<std::int32_t>(&s, cell.size() == 4 ? 10 : 5, true)
           : void(s += cell.size() == 4 ? "10\n" : "5\n");
  s += binary ? "\nCELL_DATA 8\nSCALARS label int 1\nLOOKUP_TABLE default\n"
              : "CELL_DATA 8\nSCALARS label int 1\nLOOKUP_TABLE default\n";
  for (const auto& cell : cells)
    binary ? put<std::int32_t>(&s, cell.size() == 4 ? 1 : 2, true)
           : void(s += cell.size() == 4 ? "1\n" : "2\n");
  s += binary ? "\nFIELD FieldData 2\nquality 1 8 float\n"
              : "FIELD FieldData 2\nquality 1 8 float\n";
  for (int i = 0; i < 8; ++i) binary ? put<float>(&s, 0.5f, true) : void(s += "0.5\n");
  s += binary ? "\nzone 1 8 int\n" : "zone 1 8 int\n";
  for (int i = 0; i < 8; ++i)
    binary ? put<std::int32_t>(&s, i < 3 ? 4 : 5, true) : void(s += i < 3 ? "4\n" : "5\n");
  s += binary ? "\nPOINT_DATA 8\nVECTORS fibre double\n" : "POINT_DATA 8\nVECTORS fibre double\n";
  for (int i = 0; i < 24; ++i) binary ? put<double>(&s, 1.0, true) : void(s += "1 ");
  s += "\n";
  return s;
}

enum class VtuMode { kAscii, kBase64, kBase64UInt64, kAppendedRaw, kAppendedBase64, kZlib };

// VTU with the tets and bottom triangles, Float64 points, Int64 connectivity, UInt8 types and a
// CellData Int32 "label" (1 = tet, 2 = bottom triangle).
inline std::string vtu(const CubeMesh& c, VtuMode mode) {
  std::vector<std::vector<int>> cells;
  for (const auto& t : c.tets) cells.push_back({t[0], t[1], t[2], t[3]});
  for (const auto& t : c.bottom) cells.push_back({t[0], t[1], t[2]});
  std::string points, conn, offsets, types, labels;
  for (const auto& p : c.nodes) {
    for (double x : p) put<double>(&points, x);
  }
  long long off = 0;
  for (const auto& cell : cells) {
    for (int v : cell) put<std::int64_t>(&conn, v);
    off += static_cast<long long>(cell.size());
    put<std::int64_t>(&offsets, off);
    put<std::uint8_t>(&types, cell.size() == 4 ? 10 : 5);
    put<std::int32_t>(&labels, cell.size() == 4 ? 1 : 2);
  }
  const bool header64 = mode == VtuMode::kBase64UInt64;
  const auto block = [&](const std::string& data) {
    if (mode == VtuMode::kZlib) {
      uLongf size = compressBound(data.size());
      std::string z(size, '\0');
      compress(reinterpret_cast<Bytef*>(z.data()), &size,
               reinterpret_cast<const Bytef*>(data.data()), data.size());
      z.resize(size);
      std::string header;
      for (std::uint32_t v :
           {1u, std::uint32_t(data.size()), std::uint32_t(data.size()), std::uint32_t(size)})
        put(&header, v);
      return base64(header) + base64(z);  // VTK encodes header and data separately
    }
    std::string header;
    header64 ? put<std::uint64_t>(&header, data.size())
             : put<std::uint32_t>(&header, std::uint32_t(data.size()));
    if (mode == VtuMode::kAppendedRaw) return header + data;
    if (mode == VtuMode::kBase64) return base64(header + data);  // one stream
    return base64(header) + base64(data);
  };
  std::string appended;
  const auto array = [&](const char* type, const char* name, int components,
                         const std::string& data, const std::string& ascii) {
    std::string s = std::string("<DataArray type=\"") + type + "\" Name=\"" + name +
                    "\" NumberOfComponents=\"" + std::to_string(components) + "\" ";
    if (mode == VtuMode::kAscii) return s + "format=\"ascii\">\n" + ascii + "\n</DataArray>\n";
    if (mode == VtuMode::kAppendedRaw || mode == VtuMode::kAppendedBase64) {
      s += "format=\"appended\" offset=\"" + std::to_string(appended.size()) + "\"/>\n";
      appended += block(data);
      return s;
    }
    return s + "format=\"binary\">\n  " + block(data) + "\n</DataArray>\n";
  };
  std::ostringstream pa, ca, oa, ta, la;
  pa.precision(17);
  for (const auto& p : c.nodes) pa << p[0] << " " << p[1] << " " << p[2] << "\n";
  off = 0;
  for (const auto& cell : cells) {
    for (int v : cell) ca << v << " ";
    off += static_cast<long long>(cell.size());
    oa << off << " ";
    ta << (cell.size() == 4 ? 10 : 5) << " ";
    la << (cell.size() == 4 ? 1 : 2) << " ";
  }
  std::string s =
      "<?xml version=\"1.0\"?>\n<!-- test cube -->\n<VTKFile type=\"UnstructuredGrid\" "
      "version=\"1.0\" byte_order=\"LittleEndian\"";
  if (header64) s += " header_type=\"UInt64\"";
  if (mode == VtuMode::kZlib) s += " compressor=\"vtkZLibDataCompressor\"";
  s += ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"8\" "
       "NumberOfCells=\"8\">\n<PointData>\n</PointData>\n";
  s += "<CellData Scalars=\"label\">\n" + array("Int32", "label", 1, labels, la.str()) +
       "</CellData>\n";
  s += "<Points>\n" + array("Float64", "Points", 3, points, pa.str()) + "</Points>\n<Cells>\n";
  s += array("Int64", "connectivity", 1, conn, ca.str());
  s += array("Int64", "offsets", 1, offsets, oa.str());
  s += array("UInt8", "types", 1, types, ta.str());
  s += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
  if (mode == VtuMode::kAppendedRaw)
    s += "<AppendedData encoding=\"raw\">\n_" + appended + "\n</AppendedData>\n";
  if (mode == VtuMode::kAppendedBase64)
    s += "<AppendedData encoding=\"base64\">\n_" + appended + "\n</AppendedData>\n";
  s += "</VTKFile>\n";
  return s;
}

// Medit: bottom triangles with ref 7, tets with ref 9, vertices with ref 0.
inline std::string medit(const CubeMesh& c) {
  std::ostringstream s;
  s.precision(17);
  s << "MeshVersionFormatted 2\n# test cube\nDimension\n3\n\nVertices\n" << c.nodes.size() << "\n";
  for (const auto& p : c.nodes) s << p[0] << " " << p[1] << " " << p[2] << " 0\n";
  s << "\nTriangles\n" << c.bottom.size() << "\n";
  for (const auto& t : c.bottom) s << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << " 7\n";
  s << "\nTetrahedra\n" << c.tets.size() << "\n";
  for (const auto& t : c.tets)
    s << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << " " << t[3] + 1 << " 9\n";
  s << "\nCorners\n1\n1\nEnd\n";
  return s.str();
}

// TetGen .node (with one attribute and boundary markers: 5 on the bottom nodes) and .ele (with a
// region attribute 3), indices starting at `base`.
inline std::pair<std::string, std::string> tetgen(const CubeMesh& c, int base) {
  std::ostringstream n;
  n.precision(17);
  n << "# cube\n" << c.nodes.size() << " 3 1 1\n";
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    n << i + base << "  " << c.nodes[i][0] << " " << c.nodes[i][1] << " " << c.nodes[i][2]
      << "  0.25  " << (c.nodes[i][2] == 0 ? 5 : 0) << "\n";
  }
  std::ostringstream e;
  e << c.tets.size() << " 4 1\n";
  for (std::size_t t = 0; t < c.tets.size(); ++t) {
    e << t + base;
    for (int v : c.tets[t]) e << " " << v + base;
    e << " 3\n";
  }
  e << "# generated by the test\n";
  return {n.str(), e.str()};
}

// The 12 boundary triangles of the cube, outward.
inline std::vector<std::array<int, 3>> cube_surface() {
  return {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
}

}  // namespace hapstate::test
