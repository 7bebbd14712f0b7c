// Malformed files give specific errors naming file:line; repairable defects are repaired and
// reported.
#include "cube_writers.h"
#include "mesh/load.h"
#include "mesh/raw_mesh.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace hapstate {
namespace {

using test::CubeMesh;

// MSH 2.2 ASCII with node tags i+1 and one tet element per entry of `tets`.
std::string msh2_text(const std::vector<std::array<double, 3>>& nodes,
                      const std::vector<std::array<int, 4>>& tets) {
  std::ostringstream s;
  s.precision(17);
  s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << nodes.size() << "\n";
  for (std::size_t i = 0; i < nodes.size(); ++i)
    s << i + 1 << " " << nodes[i][0] << " " << nodes[i][1] << " " << nodes[i][2] << "\n";
  s << "$EndNodes\n$Elements\n" << tets.size() << "\n";
  for (std::size_t t = 0; t < tets.size(); ++t) {
    s << t + 1 << " 4 2 1 1";
    for (int v : tets[t]) s << " " << v + 1;
    s << "\n";
  }
  s << "$EndElements\n";
  return s.str();
}

// 1-based line number of the first line containing `needle`.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

// Loading `name` with `content` throws InputError whose message contains "name:line:" (if
// line > 0) and every key word.
void expect_error(const std::string& name, const std::string& content, int line,
                  const std::vector<std::string>& words) {
  const auto path = test::write_file(name, content);
  try {
    load_mesh(path);
    FAIL() << name << ": no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::string where = path.string() + ":";  // appended: GCC 12's -Wrestrict false positive
    if (line > 0) where.append(std::to_string(line)).append(":");
    EXPECT_NE(msg.find(where), std::string::npos) << "expected '" << where << "' in: " << msg;
    for (const auto& w : words)
      EXPECT_NE(msg.find(w), std::string::npos) << "expected '" << w << "' in: " << msg;
  }
}

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

const CubeMesh kCube;

TEST(Malformed, TruncatedFile) {
  const std::string full = test::msh2(kCube, false);
  const std::string cut = full.substr(0, full.find("4 2 9 1") + 20);  // inside the first tet line
  const std::string text = cut.substr(0, cut.rfind('\n') + 1);        // whole lines only
  expect_error("trunc.msh", text, static_cast<int>(std::count(text.begin(), text.end(), '\n')),
               {"truncated", "end of file"});
}

TEST(Malformed, TruncatedBinaryBlock) {
  const std::string full = test::msh2(kCube, true);
  const std::string text = full.substr(0, full.find("$EndNodes") - 30);
  expect_error("trunc_bin.msh", text, line_of(text, "$Nodes") + 2, {"truncated", "bytes"});
}

// A count the file declares is not trusted before it is read: a tiny file that declares two
// billion nodes is an error naming the file, not an attempt to allocate tens of gigabytes.
TEST(Malformed, HugeDeclaredCountsAreErrorsNotAllocations) {
  const std::vector<std::pair<std::string, std::string>> files = {
      {"huge1.msh", "$NOD\n2000000000\n1 0 0 0\n$ENDNOD\n"},
      {"huge2.msh",
       "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2000000000\n1 0 0 0\n$EndNodes\n"},
      {"huge4.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2000000000 1 2000000000\n"
       "3 1 0 2000000000\n1\n0 0 0\n$EndNodes\n"},
      {"huge.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n2000000000\n0 0 0 1\nEnd\n"},
      {"huge.vtk",
       "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"
       "POINTS 2000000000 double\n0 0 0\n"},
  };
  for (const auto& [name, content] : files) expect_error(name, content, 0, {});
}

TEST(Malformed, WrongNodeCount) {
  const std::string text = replace_once(test::msh2(kCube, false), "$Nodes\n8\n", "$Nodes\n9\n");
  expect_error("count.msh", text, line_of(text, "$EndNodes"),
               {"node 9 of 9", "wrong node count", "'$EndNodes'"});
  const std::string fewer = replace_once(test::msh2(kCube, false), "$Nodes\n8\n", "$Nodes\n7\n");
  expect_error("count7.msh", fewer, line_of(fewer, "$EndNodes") - 1,
               {"'$EndNodes' after 7 nodes", "wrong node count"});
}

TEST(Malformed, BadNumberToken) {
  const std::string text = replace_once(test::msh2(kCube, false), "\n80 0 1 0\n", "\n80 0 1e 0\n");
  expect_error("number.msh", text, line_of(text, "80 0 1e 0"),
               {"expected node coordinate (a finite number)", "'1e'"});
}

TEST(Malformed, NonFiniteCoordinate) {
  const std::string text = replace_once(test::msh2(kCube, false), "\n80 0 1 0\n", "\n80 0 nan 0\n");
  expect_error("nan.msh", text, line_of(text, "80 0 nan 0"), {"finite", "'nan'"});
}

TEST(Malformed, ElementReferencesMissingNode) {
  const std::string text = replace_once(test::msh2(kCube, false), "4 2 9 1 100", "4 2 9 1 55");
  expect_error("missing.msh", text, line_of(text, "4 2 9 1 55"), {"node tag 55", "missing node"});
}

TEST(Malformed, UnknownElementType) {
  const std::string text = replace_once(test::msh2(kCube, false), "4 2 9 1 100", "99 2 9 1 100");
  expect_error("type.msh", text, line_of(text, "99 2 9 1 100"), {"unknown Gmsh element type 99"});
}

TEST(Malformed, HigherOrderTetUnsupported) {
  const std::string text = replace_once(test::msh2(kCube, false), "$EndElements",
                                        "9 11 2 9 1 100 90 80 70 60 50 40 30 100 90\n$EndElements");
  expect_error("tet10.msh", replace_once(text, "\n8\n1 2 2", "\n9\n1 2 2"),
               line_of(text, "9 11 2 9 1"), {"unsupported element type 11", "higher order"});
}

TEST(Malformed, UnknownFormat) {
  expect_error("cube.xyz", "whatever", 0, {"unknown mesh format '.xyz'"});
  expect_error("cube.vtk", "hello\n", 1, {"# vtk DataFile Version"});
  expect_error("cube.msh", "hello\n", 1, {"$MeshFormat"});
}

TEST(Malformed, Msh4WrongNodeCount) {
  const std::string text = replace_once(test::msh4(kCube, false), "2 8 30 100\n", "2 9 30 100\n");
  expect_error("count41.msh", text, line_of(text, "$Nodes") + 1,
               {"declares 9", "wrong node count"});
}

TEST(Malformed, VtkLegacyErrors) {
  const std::string text = test::vtk_legacy(kCube, false, false);
  const std::string more = replace_once(text, "POINTS 8 double", "POINTS 9 double");
  expect_error("count.vtk", more, line_of(more, "CELLS"), {"expected point coordinate", "'CELLS'"});
  const std::string missing = replace_once(text, "\n4 0 1 3 7\n", "\n4 0 1 3 8\n");
  expect_error("missing.vtk", missing, line_of(missing, "4 0 1 3 8"),
               {"references point 8", "missing node"});
  const std::string type = replace_once(text, "CELL_TYPES 8\n10\n", "CELL_TYPES 8\n12\n");
  expect_error("type.vtk", type, line_of(type, "4 0 1 3 7"), {"unsupported", "cell type 12"});
  const std::string bin = test::vtk_legacy(kCube, true, false);
  expect_error("trunc_bin.vtk", bin.substr(0, bin.find("CELLS") + 30), line_of(bin, "CELLS") + 1,
               {"truncated", "bytes of binary cell list"});
}

TEST(Malformed, VtuErrors) {
  const std::string text = test::vtu(kCube, test::VtuMode::kAscii);
  expect_error("trunc.vtu", text.substr(0, text.find("</Cells>")), 0, {"truncated", "missing </"});
  const std::string missing = replace_once(text, "0 1 3 7", "0 1 3 99");
  expect_error("missing.vtu", missing, line_of(missing, "Name=\"connectivity\""),
               {"references point 99", "missing node"});
  const std::string b64 = test::vtu(kCube, test::VtuMode::kBase64);
  const std::size_t at = b64.find("format=\"binary\">\n  ") + 22;
  std::string bad = b64;
  bad[at] = '*';
  expect_error("base64.vtu", bad, 0, {"invalid base64 character"});
  const std::string lz =
      replace_once(text, "type=\"UnstructuredGrid\"",
                   "type=\"UnstructuredGrid\" compressor=\"vtkLZ4DataCompressor\"");
  expect_error("lz4.vtu", lz, line_of(lz, "<VTKFile"),
               {"unsupported compressor", "vtkLZ4DataCompressor"});
  const std::string count = replace_once(text, "NumberOfPoints=\"8\"", "NumberOfPoints=\"9\"");
  expect_error("count.vtu", count, line_of(count, "1 1 1\n\n</DataArray>\n</Points>"),
               {"DataArray holds only 24 values, expected 27"});
}

TEST(Malformed, MeditAndTetGenMissingNode) {
  const std::string medit = replace_once(test::medit(kCube), "1 3 2 7", "1 3 9 7");
  expect_error("missing.mesh", medit, line_of(medit, "1 3 9 7"),
               {"references vertex 9", "missing node"});
  auto [node, ele] = test::tetgen(kCube, 1);
  test::write_file("missing_tg.node", node);
  ele = replace_once(ele, "\n1 1 2 4 8", "\n1 1 2 4 99");
  expect_error("missing_tg.ele", ele, 2, {"references point 99", "missing node"});
}

TEST(Repaired, InvertedTetIsReoriented) {
  auto tets = kCube.tets;
  std::swap(tets[2][1], tets[2][2]);
  MeshReport report;
  const Mesh m = load_mesh(test::write_file("inverted.msh", msh2_text(kCube.nodes, tets)), &report);
  EXPECT_EQ(report.reoriented, 1);
  EXPECT_EQ(m.num_tets(), 6);
  EXPECT_NEAR(test::tet_volume_sum(m), 1.0, 1e-12);
  test::expect_valid(m);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("tet 2 was negatively oriented"), std::string::npos)
      << report.warnings.front();
}

TEST(Repaired, DuplicateAndDegenerateTetsRemoved) {
  auto tets = kCube.tets;
  tets.push_back({tets[3][1], tets[3][0], tets[3][3], tets[3][2]});  // tet 6: same nodes as tet 3
  tets.push_back({0, 1, 2, 3});                                      // tet 7: flat (bottom face)
  auto nodes = kCube.nodes;
  nodes.push_back({0.5, 0.5, 1e-13});  // node 8, almost on z = 0
  tets.push_back({0, 1, 3, 8});        // tet 8: |det|/l^3 ~ 1e-13
  MeshReport report;
  const Mesh m = load_mesh(test::write_file("dupdeg.msh", msh2_text(nodes, tets)), &report);
  EXPECT_EQ(report.duplicate, 1);
  EXPECT_EQ(report.duplicate_tets, std::vector<int>{6});
  EXPECT_EQ(report.degenerate, 2);
  EXPECT_EQ(report.degenerate_tets, (std::vector<int>{7, 8}));
  EXPECT_EQ(report.unreferenced, 1);  // node 8 only served the removed tet
  EXPECT_EQ(m.num_tets(), 6);
  EXPECT_NEAR(test::tet_volume_sum(m), 1.0, 1e-12);
  test::expect_valid(m);
  const auto has = [&](const std::string& w) {
    return std::any_of(report.warnings.begin(), report.warnings.end(),
                       [&](const auto& s) { return s.find(w) != std::string::npos; });
  };
  EXPECT_TRUE(has("tet 6 duplicates tet 3"));
  EXPECT_TRUE(has("tet 7 (0-based, file order) is degenerate"));
  EXPECT_TRUE(has("tet 8 (0-based, file order) is degenerate"));
}

TEST(Repaired, UnreferencedNodeReportedAndKept) {
  auto nodes = kCube.nodes;
  nodes.insert(nodes.begin() + 3, {5.0, 5.0, 5.0});  // becomes node 3
  auto tets = kCube.tets;
  for (auto& t : tets) {
    for (int& v : t) v += v >= 3 ? 1 : 0;
  }
  MeshReport report;
  const Mesh m = load_mesh(test::write_file("unref.msh", msh2_text(nodes, tets)), &report);
  EXPECT_EQ(report.unreferenced, 1);
  EXPECT_EQ(report.unreferenced_nodes, std::vector<int>{3});
  EXPECT_EQ(m.num_nodes(), 9);
  EXPECT_EQ(m.nodes(0, 3), 5.0);
  EXPECT_EQ(m.surface.cols(), 12);
  test::expect_valid(m);
}

TEST(Repaired, FaceSharedByThreeTetsIsAnError) {
  // Faces (0, a, 7) are shared by two cube tets; a third tet on one of them overlaps.
  auto nodes = kCube.nodes;
  nodes.push_back({-1.0, 2.0, 0.5});
  auto tets = kCube.tets;
  tets.push_back({tets[0][0], tets[0][1], tets[0][3], 8});
  expect_error("overlap.msh", msh2_text(nodes, tets), 0, {"shared by 3 tets", "non-manifold"});
}

TEST(Repaired, NoTetsIsAnError) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
      "$Elements\n1\n1 2 2 1 1 1 2 3\n$EndElements\n";
  expect_error("notets.msh", text, 0, {"no linear tetrahedra"});
}

// A file may name any node tags: the tag table grows with the nodes the file holds, not with the
// largest tag (fuzz_mesh_tetgen found a 40-byte file whose tag 6e7 made a 268 MB table).
TEST(NodeTagTable, MemoryFollowsTheNodesNotTheTags) {
  NodeTags tags;
  EXPECT_TRUE(tags.add(60000000, 0));
  EXPECT_TRUE(tags.add(5, 1));
  EXPECT_TRUE(tags.add(-7, 2));
  EXPECT_LE(tags.dense_size(), 8u * 3u + 1024u);
  EXPECT_EQ(tags.find(60000000), 0);
  EXPECT_EQ(tags.find(5), 1);
  EXPECT_EQ(tags.find(-7), 2);
  EXPECT_EQ(tags.find(6), -1);
  EXPECT_EQ(tags.find(59999999), -1);
  // A tag stored in the hash map while it was beyond the dense range stays a duplicate once the
  // range has grown past it, and the other way round.
  NodeTags grown;
  EXPECT_TRUE(grown.add(2000, 0));  // beyond 8 x 1 + 1024: hash map
  for (int id = 1; id <= 200; ++id) EXPECT_TRUE(grown.add(id, id));
  EXPECT_FALSE(grown.add(2000, 201));  // now inside the dense range: still a duplicate
  EXPECT_FALSE(grown.add(150, 202));
  EXPECT_EQ(grown.find(2000), 0);
  EXPECT_EQ(grown.find(150), 150);
  // Tags in reverse order (a large first tag) are all found.
  NodeTags reverse;
  for (int id = 0; id < 5000; ++id) EXPECT_TRUE(reverse.add(5000 - id, id));
  for (int id = 0; id < 5000; ++id) EXPECT_EQ(reverse.find(5000 - id), id);
  EXPECT_EQ(reverse.find(0), -1);
}

TEST(Malformed, HugeNodeTagIsNoHugeTable) {
  // The fuzzer's input, as text: a TetGen .node file with one point whose index is 60 000 000.
  const auto path = test::write_file("huge_tag.node", "1 3 0 0\n60000000 0 0 0\n");
  test::write_file("huge_tag.ele", "0 4 0\n");
  EXPECT_THROW(load_mesh(path.parent_path() / "huge_tag.ele"), InputError);
}

}  // namespace
}  // namespace hapstate
