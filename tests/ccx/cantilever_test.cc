// Our path solver against CalculiX on the same mesh and path: a 10 x 1 x 1 cantilever (a tet
// mesh of a box, x = 0 clamped) (a) grabbed at the free end and pulled sideways through 30 % of
// its length, (b) pushed down at mid-span by a patch of top-face nodes. Per law (stvk, neohooke,
// mooney) the forces and displacements must agree to 1e-4 of their maxima over the path.
// The same results also go through tools/ccx_compare.py in the documented CSV formats.
#include "ccx/deck.h"
#include "ccx/read_dat.h"
#include "ccx/run.h"
#include "mesh/box_mesh.h"
#include "solver/path_solver.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace hapstate {
namespace {

constexpr double kYoung = 5e6;  // Pa (rubber-like), 1 cm x 1 cm x 10 cm: forces of ~0.1-1 N
constexpr double kPoisson = 0.3;
constexpr double kUnit = 0.01;
constexpr double kRtol = 1e-4;

MaterialConstants constants(Law law) {
  MaterialConstants c;
  c.law = law;
  c.mu = kYoung / (2 * (1 + kPoisson));
  c.lambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
  c.d1 = 2 / (kYoung / (3 * (1 - 2 * kPoisson)));
  c.c10 = law == Law::kMooney ? 0.8 * c.mu / 2 : c.mu / 2;
  c.c01 = law == Law::kMooney ? 0.2 * c.mu / 2 : 0;
  return c;
}

enum class Load { kGrabEnd, kPushPatch };

struct Case {
  Law law;
  Load load;
};

// The beam with x = 0 clamped and the probe nodes (all three components follow the probe).
Problem beam_problem(const Case& k, std::vector<Eigen::Vector3d>* path) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 1, 1), 20, 2, 2);
  p.unit = kUnit;
  p.material = constants(k.law);
  const int n = p.mesh.num_nodes();
  p.constraints.role.assign(3 * n, DofRole::kFree);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = p.mesh.nodes.col(i);
    const bool probe = k.load == Load::kGrabEnd ? (x - Eigen::Vector3d(10, 0.5, 0.5)).norm() < 1e-12
                                                : x.z() == 1 && x.x() >= 4 && x.x() <= 6;
    if (x.x() == 0) {
      for (int c = 0; c < 3; ++c) p.constraints.role[3 * i + c] = DofRole::kFixed;
    } else if (probe) {
      for (int c = 0; c < 3; ++c) p.constraints.role[3 * i + c] = DofRole::kProbe;
      p.constraints.probe_nodes.push_back(i);
    }
  }
  p.probe_rest.setZero();
  for (int i : p.constraints.probe_nodes) p.probe_rest += p.mesh.nodes.col(i);
  p.probe_rest /= static_cast<double>(p.constraints.probe_nodes.size());
  // (a) 3 units (30 % of the length) sideways in 5 points; (b) 1.5 units down in 5 points.
  const Eigen::Vector3d end =
      k.load == Load::kGrabEnd ? Eigen::Vector3d(0, 3, 0) : Eigen::Vector3d(0, 0, -1.5);
  path->clear();
  for (int j = 1; j <= 5; ++j) path->push_back(p.probe_rest + end * (j / 5.0));
  return p;
}

std::string case_name(const Case& k) {
  return std::string(law_name(k.law)) + (k.load == Load::kGrabEnd ? "_grab_end" : "_push_patch");
}

class CcxCantilever : public ::testing::TestWithParam<Case> {};

TEST_P(CcxCantilever, PathSolverMatchesCalculix) {
  std::vector<Eigen::Vector3d> path;
  Problem problem = beam_problem(GetParam(), &path);
  problem.solver.tolerance = 1e-10;
  const std::string name = case_name(GetParam());
  const auto dir =
      std::filesystem::path(HAPSTATE_BINARY_DIR) / "tests" / "ccx_out" / ("cantilever_" + name);
  std::filesystem::remove_all(dir);
  write_ccx_deck(problem, path, dir);
  run_ccx(dir);
  const auto ccx = ccx_path_results(
      problem, read_ccx_dat(dir / (std::string(kCcxJobName) + ".dat")), path.size());

  // Our solve, written in the formats ccx_compare.py reads (docs/calculix.md).
  PathSolver solver(problem);
  std::ofstream ours(dir / "ours.csv"), ours_u(dir / "ours_displacements.csv");
  ours.precision(17);
  ours_u.precision(17);
  ours << "step,x,y,z,fx,fy,fz,residual,iterations,substeps,wall_ms\n";
  ours_u << "step,node,ux,uy,uz\n";
  std::vector<Eigen::Vector3d> force(path.size());
  std::vector<Eigen::Matrix3Xd> u(path.size());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const MoveResult r = solver.move_to(path[k] - problem.probe_rest);
    ASSERT_TRUE(r.ok) << name << " point " << k + 1 << ": " << r.reason;
    force[k] = solver.force_felt();
    u[k] = solver.displacements();
    ours << k + 1 << "," << path[k].x() << "," << path[k].y() << "," << path[k].z() << ","
         << force[k].x() << "," << force[k].y() << "," << force[k].z() << "," << r.residual << ","
         << r.iterations << "," << r.substeps << "," << r.wall_ms << "\n";
    for (int i = 0; i < problem.mesh.num_nodes(); ++i) {
      ours_u << k + 1 << "," << i << "," << u[k](0, i) << "," << u[k](1, i) << "," << u[k](2, i)
             << "\n";
    }
  }
  ours.close();
  ours_u.close();

  double f_scale = 0, u_scale = 0, tip = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    f_scale = std::max(f_scale, ccx[k].force_felt.norm());
    u_scale = std::max(u_scale, ccx[k].displacement.cwiseAbs().maxCoeff());
  }
  tip = u_scale;
  double worst_f = 0, worst_u = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double ef = (force[k] - ccx[k].force_felt).norm() / f_scale;
    const double eu = (u[k] - ccx[k].displacement).cwiseAbs().maxCoeff() / u_scale;
    worst_f = std::max(worst_f, ef);
    worst_u = std::max(worst_u, eu);
    std::printf(
        "  %-22s pt %zu: felt ours (%+.6e %+.6e %+.6e) ccx (%+.6e %+.6e %+.6e) "
        "err_f %.1e err_u %.1e\n",
        name.c_str(), k + 1, force[k].x(), force[k].y(), force[k].z(), ccx[k].force_felt.x(),
        ccx[k].force_felt.y(), ccx[k].force_felt.z(), ef, eu);
  }
  std::printf("  %-22s max |f| %.4e N, max |u| %.4f mesh units: worst err_f %.2e, err_u %.2e\n",
              name.c_str(), f_scale, tip, worst_f, worst_u);
  EXPECT_LE(worst_f, kRtol);
  EXPECT_LE(worst_u, kRtol);
  if (GetParam().load == Load::kGrabEnd) {
    EXPECT_GE(tip, 2.5);  // >= 25 % of the length
  }

  // The comparison tool must agree (exit 0) on the same data.
  const std::string cmd = "python3 " HAPSTATE_SOURCE_DIR "/tools/ccx_compare.py --ccx-dir '" +
                          dir.string() + "' --ours '" + (dir / "ours.csv").string() +
                          "' --ours-displacements '" + (dir / "ours_displacements.csv").string() +
                          "' --rtol 1e-4 > '" + (dir / "compare.txt").string() + "' 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << "see " << (dir / "compare.txt").string();
}

INSTANTIATE_TEST_SUITE_P(
    Laws, CcxCantilever,
    ::testing::Values(Case{Law::kStvk, Load::kGrabEnd}, Case{Law::kNeoHooke, Load::kGrabEnd},
                      Case{Law::kMooney, Load::kGrabEnd}, Case{Law::kStvk, Load::kPushPatch},
                      Case{Law::kNeoHooke, Load::kPushPatch}, Case{Law::kMooney, Load::kPushPatch}),
    [](const auto& info) { return case_name(info.param); });

}  // namespace
}  // namespace hapstate
