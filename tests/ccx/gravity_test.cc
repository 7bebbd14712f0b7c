// Gravity and elastic supports against CalculiX on the same mesh (issue 40):
//  (a) a slender neo-Hookean cantilever (10 x 1 x 1 cm, x = 0 clamped) sagging under its own
//      weight by more than half its length: the loaded rest state (hapstate-solve --rest's
//      solve) must match ccx's *DLOAD GRAV step to 1e-4 of the tip displacement; then its tip is
//      grabbed and lifted, and forces and displacements must agree to 1e-4 of their maxima;
//  (b) a soft block held only by an elastic foundation under its bottom face ([[support]],
//      SPRING1 elements in ccx) under gravity, its top centre pushed down and sideways;
//  (c) the bundled liver's loaded rest state (its far lobe swings down by 6 cm).
// Both scenes are parsed from TOML and bound by bind_scene, as a user's scene would be.
#include "ccx/deck.h"
#include "ccx/read_dat.h"
#include "ccx/run.h"
#include "mesh/box_mesh.h"
#include "scene/bind.h"
#include "scene/scene.h"
#include "solver/path_solver.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace hapstate {
namespace {

constexpr double kRtol = 1e-4;

std::string slurp(const std::string& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

Problem problem_of(const std::string& text, const Mesh& mesh) {
  SceneParseOptions options;
  options.check_files = false;
  return bind_scene(parse_scene(text, "gravity_test.toml", options), mesh);
}

std::filesystem::path out_dir(const std::string& name) {
  const auto dir = std::filesystem::path(HAPSTATE_BINARY_DIR) / "tests" / "ccx_out" / name;
  std::filesystem::remove_all(dir);
  return dir;
}

// Our path from the rest state against ccx's: worst relative errors of the felt force and the
// displacements over the path (scaled by their maxima).
void compare_path(const Problem& problem, const std::vector<Eigen::Vector3d>& path,
                  const std::string& name, double* worst_f, double* worst_u) {
  const auto dir = out_dir(name + "_path");
  write_ccx_deck(problem, path, dir);
  run_ccx(dir);
  const auto ccx = ccx_path_results(
      problem, read_ccx_dat(dir / (std::string(kCcxJobName) + ".dat")), path.size());
  PathSolver solver(problem);
  std::vector<Eigen::Vector3d> force(path.size());
  std::vector<Eigen::Matrix3Xd> u(path.size());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const MoveResult r = solver.move_to(path[k] - problem.probe_rest);
    ASSERT_TRUE(r.ok) << name << " point " << k + 1 << ": " << r.reason;
    force[k] = solver.force_felt();
    u[k] = solver.displacements();
  }
  double f_scale = 0, u_scale = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    f_scale = std::max(f_scale, ccx[k].force_felt.norm());
    u_scale = std::max(u_scale, ccx[k].displacement.cwiseAbs().maxCoeff());
  }
  *worst_f = *worst_u = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double ef = (force[k] - ccx[k].force_felt).norm() / f_scale;
    const double eu = (u[k] - ccx[k].displacement).cwiseAbs().maxCoeff() / u_scale;
    *worst_f = std::max(*worst_f, ef);
    *worst_u = std::max(*worst_u, eu);
    std::printf(
        "  %s pt %zu: felt ours (%+.6e %+.6e %+.6e) ccx (%+.6e %+.6e %+.6e) err_f %.1e "
        "err_u %.1e\n",
        name.c_str(), k + 1, force[k].x(), force[k].y(), force[k].z(), ccx[k].force_felt.x(),
        ccx[k].force_felt.y(), ccx[k].force_felt.z(), ef, eu);
  }
}

// The rest state of `problem` against ccx's gravity step: the largest node displacement
// difference over the largest displacement.
double compare_rest(const Problem& problem, const std::string& name, double* largest) {
  const auto dir = out_dir(name + "_rest");
  write_ccx_deck(problem, {}, dir);
  run_ccx(dir);
  const Eigen::Matrix3Xd ccx =
      ccx_rest_displacement(problem, read_ccx_dat(dir / (std::string(kCcxJobName) + ".dat")));
  const Eigen::Matrix3Xd ours =
      Eigen::Map<const Eigen::Matrix3Xd>(problem.rest_m.data(), 3, problem.mesh.num_nodes()) /
      problem.unit;
  *largest = ccx.colwise().norm().maxCoeff();
  const double err = (ours - ccx).colwise().norm().maxCoeff() / *largest;
  std::printf("  %s rest: largest displacement ours %.6f ccx %.6f mesh units, err %.2e\n",
              name.c_str(), ours.colwise().norm().maxCoeff(), *largest, err);
  return err;
}

TEST(CcxGravity, SaggingCantileverMatchesCalculix) {
  const std::string scene = R"(
[mesh]
file = "beam.msh"
unit = 0.01
[material]
law = "neohooke"
young = 1e5
poisson = 0.3
density = 1000
[loads]
gravity = [0, 0, -9.81]
[[fixed]]
group = "xmin"
[probe]
point = [10, 0.5, 0.5]
max_force = 1
[grid]
spacing = 0.5
[solver]
tolerance = 1e-10
)";
  const Mesh mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 1, 1), 20, 2, 2);
  const Problem problem = problem_of(scene, mesh);
  double largest = 0;
  EXPECT_LE(compare_rest(problem, "gravity_cantilever", &largest), kRtol);
  // The tip (the grabbed node) sags by more than half the length.
  EXPECT_GT(-problem.probe_sag.z(), 5.0);
  EXPECT_GT(largest, 5.0);
  // Lift the tip from where it hangs by 2 cm in 3 points.
  std::vector<Eigen::Vector3d> path;
  for (int k = 1; k <= 3; ++k)
    path.push_back(problem.probe_rest + Eigen::Vector3d(0, 0, 2.0 * k / 3));
  double worst_f = 0, worst_u = 0;
  compare_path(problem, path, "gravity_cantilever", &worst_f, &worst_u);
  EXPECT_LE(worst_f, kRtol);
  EXPECT_LE(worst_u, kRtol);
}

TEST(CcxGravity, BlockOnElasticFoundationMatchesCalculix) {
  const std::string scene = R"(
[mesh]
file = "block.msh"
unit = 0.01
[material]
law = "neohooke"
young = 5000
poisson = 0.45
density = 1000
[loads]
gravity = [0.5, 0, -9.81]
[[support]]
group = "zmin"
stiffness = 2e5
[probe]
point = [2, 2, 2]
max_force = 1
[grid]
spacing = 0.5
[solver]
tolerance = 1e-10
)";
  const Mesh mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(4, 4, 2), 4, 4, 2);
  const Problem problem = problem_of(scene, mesh);
  double largest = 0;
  EXPECT_LE(compare_rest(problem, "gravity_foundation", &largest), kRtol);
  EXPECT_GT(largest, 0.05);  // the foundation gives way under the block's weight
  std::vector<Eigen::Vector3d> path;
  for (int k = 1; k <= 2; ++k) path.push_back(problem.probe_rest + Eigen::Vector3d(0, 0, -0.3 * k));
  path.push_back(path.back() + Eigen::Vector3d(0.4, 0.2, 0));
  double worst_f = 0, worst_u = 0;
  compare_path(problem, path, "gravity_foundation", &worst_f, &worst_u);
  EXPECT_LE(worst_f, kRtol);
  EXPECT_LE(worst_u, kRtol);
}

// (c) A real organ: the bundled liver (181 nodes, neo-Hooke 5 kPa, held at its ligament) under
// its own weight swings its far lobe down by about 6 cm; the rest state agrees with ccx's.
TEST(CcxGravity, SaggingLiverRestStateMatchesCalculix) {
  std::string text = slurp(HAPSTATE_SOURCE_DIR "/pipelines/liver/scene.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("poisson = 0.45", "poisson = 0.45\ndensity = 1000\n[loads]\ngravity = [0, -9.81, 0]");
  replace("../../data/meshes/liver.msh", HAPSTATE_SOURCE_DIR "/data/meshes/liver.msh");
  SceneParseOptions options;
  const Problem problem = build_problem(parse_scene(text, "liver_gravity.toml", options));
  double largest = 0;
  EXPECT_LE(compare_rest(problem, "gravity_liver", &largest), kRtol);
  EXPECT_GT(largest, 3.0);  // cm
}

}  // namespace
}  // namespace hapstate
