// The carving fallback for closed but self-intersecting surfaces (libstate/mesh/carve.h): the
// shared grid layout, the bundled liver-smooth.obj and synthetic overlapping cubes.
#include "mesh/carve.h"
#include "cube_writers.h"
#include "mesh/box_mesh.h"
#include "mesh/load.h"
#include "mesh/surface.h"
#include "mesh/winding_number.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace hapstate {
namespace {

std::string warnings_text(const MeshReport& r) {
  std::string all;
  for (const auto& w : r.warnings) all += w + "\n";
  return all;
}

// The test shapes are turned by this rotation so that their faces cut the carving grid at every
// angle and offset (axis-aligned faces would all sit at one offset in their cells, a systematic
// error of up to a quarter cell).
Eigen::Matrix3d tilt() {
  return Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

// Cubes tilt() * [lo, lo + edge]^3 written into one OBJ, outward faces (or all flipped).
std::string cubes_obj(const std::vector<std::pair<Eigen::Vector3d, double>>& cubes,
                      bool flip = false) {
  std::ostringstream o;
  o.precision(17);
  int base = 0;
  for (const auto& [lo, edge] : cubes) {
    for (int v = 0; v < 8; ++v) {
      const Eigen::Vector3d p =
          tilt() * (lo + edge * Eigen::Vector3d(v & 1, (v >> 1) & 1, (v >> 2) & 1));
      o << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
    for (const auto& f : test::cube_surface()) {
      if (flip) {
        o << "f " << base + f[0] + 1 << " " << base + f[2] + 1 << " " << base + f[1] + 1 << "\n";
      } else {
        o << "f " << base + f[0] + 1 << " " << base + f[1] + 1 << " " << base + f[2] + 1 << "\n";
      }
    }
    base += 8;
  }
  return o.str();
}

// Every boundary node's boundary faces form one fan (a disk), not several touching at the node.
void expect_manifold_nodes(const Mesh& m) {
  std::map<int, std::map<int, int>> next;  // node -> (next corner -> following corner) per face
  for (int f = 0; f < m.surface.cols(); ++f) {
    for (int k = 0; k < 3; ++k)
      next[m.surface(k, f)][m.surface((k + 1) % 3, f)] = m.surface((k + 2) % 3, f);
  }
  for (const auto& [node, ring] : next) {
    int steps = 0;
    int v = ring.begin()->first;
    do {
      const auto it = ring.find(v);
      ASSERT_NE(it, ring.end()) << "open fan at node " << node;
      v = it->second;
      ++steps;
    } while (v != ring.begin()->first && steps <= static_cast<int>(ring.size()));
    EXPECT_EQ(steps, static_cast<int>(ring.size()))
        << "node " << node << " joins several surface sheets";
  }
}

TEST(Carve, GridTetsArePositiveAndStarsComplete) {
  const TetGrid g{Eigen::Vector3d(-1, 2, 0.5), Eigen::Vector3d(0.3, 0.4, 0.5), 3, 4, 5};
  for (int t = 0; t < g.num_tets(); ++t) {
    const auto n = g.tet(t);
    Eigen::Matrix3d e;
    e << g.node(n[1]) - g.node(n[0]), g.node(n[2]) - g.node(n[0]), g.node(n[3]) - g.node(n[0]);
    ASSERT_GT(e.determinant(), 0.0) << "tet " << t;
  }
  std::array<int, 24> star{};
  const int inner = g.node_id(1, 2, 3);
  ASSERT_EQ(g.tets_around_node(inner, &star), 24);
  for (int t : star) {
    const auto n = g.tet(t);
    EXPECT_NE(std::find(n.begin(), n.end(), inner), n.end());
  }
  EXPECT_EQ(g.tets_around_node(g.node_id(0, 0, 0), &star), 6);  // box corner: 0 is in all 6
  // The box mesh is built on the same grid: nothing for validation to re-orient.
  const Mesh box = make_box_mesh(g.origin, g.size, 3, 4, 5);
  test::expect_valid(box);
  EXPECT_EQ(box.num_tets(), g.num_tets());
  EXPECT_NEAR(test::tet_volume_sum(box), 0.3 * 0.4 * 0.5, 1e-12);
}

TEST(Carve, CellSizeRule) {
  bool capped = true;
  // Liver-like: target tet count governs.
  const double h = carve_cell_size(Eigen::Vector3d(6.39, 4.91, 4.41), 39.27, &capped);
  EXPECT_FALSE(capped);
  EXPECT_NEAR(h, std::cbrt(6 * 39.27 / kCarveTargetTets), 1e-12);
  // A slab: at least 8 cells across the thin side.
  EXPECT_NEAR(carve_cell_size(Eigen::Vector3d(2, 2, 0.4), 1.6, &capped), 0.05, 1e-12);
  EXPECT_FALSE(capped);
  // A sheet too thin for 8 cells within the cell budget: coarser grid, reported.
  const double sheet = carve_cell_size(Eigen::Vector3d(100, 100, 0.01), 100, &capped);
  EXPECT_TRUE(capped);
  EXPECT_LE(
      (std::ceil(100 / sheet) + 2) * (std::ceil(100 / sheet) + 2) * (std::ceil(0.01 / sheet) + 2),
      kCarveMaxCells);
}

TEST(Carve, LiverSmoothObjImportsByCarving) {
  const std::string path = std::string(HAPSTATE_TEST_DATA) + "/meshes/liver-smooth.obj";
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const TriangleSurface s = parse_obj(text, path);
  const double surface_volume = WindingNumber(s).enclosed_volume();
  EXPECT_NEAR(surface_volume, 39.27, 0.01);

  const auto start = std::chrono::steady_clock::now();
  MeshReport report;
  const Mesh m = load_mesh(path, &report);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string warnings = warnings_text(report);
  std::cout << "liver-smooth.obj: " << m.num_nodes() << " nodes, " << m.num_tets() << " tets, "
            << m.surface.cols() << " boundary faces, volume " << test::tet_volume_sum(m) << " in "
            << seconds << " s\n"
            << warnings;

  EXPECT_EQ(report.format, "obj-surface");
  test::expect_valid(m);  // positive tets, closed outward boundary
  expect_manifold_nodes(m);
  EXPECT_EQ(report.reoriented, 0);
  EXPECT_EQ(report.degenerate, 0);
  EXPECT_EQ(report.unreferenced, 0);
  EXPECT_NEAR(test::tet_volume_sum(m) / surface_volume, 1.0, 0.10);
  // Shape: snapping keeps det >= 0.2 h^3, so no tet comes near the degenerate threshold (1e-9).
  double worst = 1e300;
  for (int t = 0; t < m.num_tets(); ++t) {
    double longest = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b)
        longest = std::max(longest, (m.nodes.col(m.tets(a, t)) - m.nodes.col(m.tets(b, t))).norm());
    }
    worst = std::min(worst, 6 * test::signed_volume(m, t) / (longest * longest * longest));
  }
  std::cout << "worst det / l_max^3 = " << worst << "\n";
  EXPECT_GT(worst, 3e-3);
  EXPECT_GE(m.num_tets(), 5000);
  EXPECT_LE(m.num_tets(), 20000);
  EXPECT_NE(warnings.find("liver-smooth.obj: the surface self-intersects near (-2.09"),
            std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find("liver-smooth.obj:5207 is crossed by the edge"), std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find("the volume was carved on a grid of cell size h = "), std::string::npos)
      << warnings;
  const std::string count =
      std::to_string(m.num_tets()) + " tets, enclosed-volume ratio carved/surface = ";
  EXPECT_NE(warnings.find(count), std::string::npos) << warnings;
  // The carved volume lies inside the surface's bounding box, give or take a cell.
  const Eigen::Vector3d lo = m.nodes.rowwise().minCoeff();
  const Eigen::Vector3d hi = m.nodes.rowwise().maxCoeff();
  EXPECT_GT(lo.x(), -4.66 - 0.3);
  EXPECT_LT(hi.x(), 1.73 + 0.3);
}

TEST(Carve, TheStrictCheckStillNamesTheCrossing) {
  const std::string path = std::string(HAPSTATE_TEST_DATA) + "/meshes/liver-smooth.obj";
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    check_closed_surface(parse_obj(text, path));
    FAIL() << "self-intersection not found";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("liver-smooth.obj:5207: self-intersecting surface"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("near (-2.09"), std::string::npos) << msg;
  }
}

// Unit cube [0,1]^3 and [0.5,1.5]^3 (tilted) in one OBJ: union volume 2 - 0.5^3 = 1.875.
constexpr double kUnionVolume = 1.875;

TEST(Carve, OverlappingCubesImportAsTheirUnion) {
  for (const bool flip : {false, true}) {
    MeshReport report;
    const Mesh m = load_mesh(test::write_file(flip ? "cubes_in.obj" : "cubes.obj",
                                              cubes_obj({{Eigen::Vector3d(0, 0, 0), 1.0},
                                                         {Eigen::Vector3d(0.5, 0.5, 0.5), 1.0}},
                                                        flip)),
                             &report);
    const std::string warnings = warnings_text(report);
    std::cout << (flip ? "inward" : "outward") << " cubes: " << m.num_tets() << " tets, volume "
              << test::tet_volume_sum(m) << "\n"
              << warnings;
    test::expect_valid(m);
    expect_manifold_nodes(m);
    // Stair-stepped faces at cell size h ~ 0.1, cut at all angles: within 3 %.
    EXPECT_NEAR(test::tet_volume_sum(m), kUnionVolume, 0.03 * kUnionVolume);
    EXPECT_NE(warnings.find("the surface self-intersects near ("), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("carved on a grid of cell size h = "), std::string::npos) << warnings;
    EXPECT_EQ(report.reoriented, 0);
  }
}

TEST(Carve, SnappingMovesMostBoundaryNodesOntoTheSurface) {
  const TriangleSurface s = parse_obj(
      cubes_obj({{Eigen::Vector3d(0, 0, 0), 1.0}, {Eigen::Vector3d(0.5, 0.5, 0.5), 1.0}}), "cubes");
  const CarveResult stairs = carve_surface(s, /*snap=*/false);
  const CarveResult snapped = carve_surface(s);
  EXPECT_EQ(stairs.snapped_nodes, 0);
  EXPECT_EQ(stairs.tets, snapped.tets);  // same tets, only boundary nodes move
  EXPECT_GT(snapped.boundary_nodes, 1000);
  EXPECT_GT(snapped.snapped_nodes, 0.8 * snapped.boundary_nodes);
  // Sharp cube edges and corners are cut by the snapped chords: a little volume is lost.
  EXPECT_NEAR(stairs.carved_volume, kUnionVolume, 0.01 * kUnionVolume);
  EXPECT_NEAR(snapped.carved_volume, kUnionVolume, 0.02 * kUnionVolume);
  EXPECT_NEAR(snapped.surface_volume, 2.0,
              1e-12);  // the overlap counts twice in the surface's own volume
  std::cout << "stairs " << stairs.carved_volume << ", snapped " << snapped.carved_volume << " ("
            << snapped.snapped_nodes << " of " << snapped.boundary_nodes << " nodes), repair +"
            << snapped.added_tets << " -" << snapped.removed_tets << " tets\n";
}

TEST(Carve, OnlyTheLargestPieceIsKept) {
  MeshReport report;
  const Mesh m = load_mesh(
      test::write_file("cubes_and_island.obj", cubes_obj({{Eigen::Vector3d(0, 0, 0), 1.0},
                                                          {Eigen::Vector3d(0.5, 0.5, 0.5), 1.0},
                                                          {Eigen::Vector3d(2.5, 0, 0), 0.5}})),
      &report);
  const std::string warnings = warnings_text(report);
  test::expect_valid(m);
  const Eigen::Matrix3Xd unturned = tilt().transpose() * m.nodes;
  EXPECT_LT(unturned.row(0).maxCoeff(), 2.0);  // the island at x >= 2.5 is gone
  EXPECT_NEAR(test::tet_volume_sum(m), kUnionVolume, 0.03 * kUnionVolume);
  EXPECT_NE(warnings.find("kept the largest"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("dropped 1 smaller piece ("), std::string::npos) << warnings;
}

TEST(Carve, OpenSelfIntersectingSurfaceIsStillAnError) {
  std::string text =
      cubes_obj({{Eigen::Vector3d(0, 0, 0), 1.0}, {Eigen::Vector3d(0.5, 0.5, 0.5), 1.0}});
  text = text.substr(0, text.rfind("f "));  // drop the last triangle: a hole
  try {
    load_mesh(test::write_file("open_cubes.obj", text));
    FAIL() << "open surface accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open surface"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapstate
