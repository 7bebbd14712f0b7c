// The numerical stress suite: its geometry helpers (tet quality, slivers, principal stretches)
// against closed forms, and the real hapstate-stress executable on its CI subset (--quick):
// every case converged with finite outputs or failed with a recorded reason, none hit the
// wall-time cap, the exit code, and cases known to converge really do.
#include "eval/stress_case.h"
#include "eval/stress_mesh.h"
#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace hapstate {
namespace {

namespace fs = std::filesystem;

TEST(StressMesh, QualityOfRegularAndFlatTets) {
  // The regular tetrahedron: q = 1; the Kuhn tet of a cube (the box mesh's): 3 r_in / r_circ
  // with r_in = 3 V / area = (1/2) / (1 + sqrt 2), r_circ = sqrt 3 / 2 (the cube's centre).
  const Eigen::Vector3d a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  EXPECT_NEAR(tet_quality(a, c, b, d), 1.0, 1e-12);
  EXPECT_NEAR(tet_quality(a, b, c, d), -1.0, 1e-12);  // inverted (negative volume): negative
  const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), xy(1, 1, 0), xyz(1, 1, 1);
  EXPECT_NEAR(tet_quality(o, x, xy, xyz), 1.5 / (1.0 + std::sqrt(2.0)) / (std::sqrt(3.0) / 2),
              1e-12);
  // A sliver: four nearly coplanar points.
  const double sliver = tet_quality(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                    Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 1e-3));
  EXPECT_GT(sliver, 0);
  EXPECT_LT(sliver, 0.01);
}

TEST(StressMesh, PerturbedBoxHasSliversAndAnUnchangedSurface) {
  const Mesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 1, 1), 8, 4, 4);
  const Mesh sliver = perturb_interior(box, 0.45, 0.02, 15);
  EXPECT_GT(min_tet_quality(box), 0.5);
  const double q = min_tet_quality(sliver);
  EXPECT_GE(q, 0.02);
  EXPECT_LT(q, 0.1);
  for (int n : box.groups.at("xmin")) EXPECT_EQ(box.nodes.col(n), sliver.nodes.col(n));
  EXPECT_GT((box.nodes - sliver.nodes).cwiseAbs().maxCoeff(), 0.02);
  // The same seed, the same mesh.
  EXPECT_EQ(perturb_interior(box, 0.45, 0.02, 15).nodes, sliver.nodes);
}

TEST(StressMesh, StretchRangeOfAHomogeneousDeformation) {
  const Mesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 1, 1), 2, 1, 1);
  Eigen::Matrix3Xd u(3, box.num_nodes());
  const Eigen::Matrix3d f = Eigen::Vector3d(1.5, 0.8, 0.9).asDiagonal();
  for (int n = 0; n < box.num_nodes(); ++n)
    u.col(n) = (f - Eigen::Matrix3d::Identity()) * box.nodes.col(n);
  const StretchRange r = stretch_range(box, u);
  EXPECT_NEAR(r.max_stretch, 1.5, 1e-12);
  EXPECT_NEAR(r.min_stretch, 0.8, 1e-12);
  EXPECT_NEAR(r.min_jacobian, 1.5 * 0.8 * 0.9, 1e-12);
}

TEST(StressCase, MatricesHaveTheDocumentedSize) {
  EXPECT_EQ(stress_matrix(true).size(), 720u);
  EXPECT_EQ(filter_cases(stress_matrix(true), "stvk,nu0.4999,compress").size(), 12u);
}

// The two solver fixes the suite led to (docs/benchmarks.md): each case failed before its fix
// (in one move, and for the contact case also in quarter-grid moves) and converges now.
TEST(StressCase, NearlyIncompressibleCasesTheSolverFixesConverge) {
  // Frictionless contact at nu 0.4999: the penalty's stiffness scale is the shear share of the
  // tangent's diagonal (before: line search failures at any step size).
  for (Law law : {Law::kLinear, Law::kNeoHooke}) {
    const StressCase c{law,
                       0.4999,
                       StressLoad::kCompress,
                       StressStep::kWhole,
                       StressMesh::kSliver,
                       StressProbe::kContact};
    const StressOutcome o = run_stress_case(c, 60, false);
    EXPECT_EQ(o.status, "converged") << c.id() << ": " << o.reason;
    EXPECT_GT(o.max_force, 0) << c.id();
    EXPECT_LE(o.strain.min_stretch, 0.8) << c.id();  // the sphere really pressed
  }
  // Newton's budget while it converges: StVK at nu 0.499 compressed by 30 % in grid steps needs
  // more than 30 iterations in one solve (before: max_iterations after 11 cut-backs).
  const StressCase c{
      Law::kStvk,         0.499, StressLoad::kCompress, StressStep::kGrid, StressMesh::kRegular,
      StressProbe::kPatch};
  const StressOutcome o = run_stress_case(c, 60, false);
  EXPECT_EQ(o.status, "converged") << o.reason;
  EXPECT_EQ(o.moves_done, 3);
  EXPECT_LE(o.strain.min_stretch, 0.7);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool in_quotes = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (in_quotes && ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cells.back() += '"';
      ++i;
    } else if (ch == '"') {
      in_quotes = !in_quotes;
    } else if (ch == ',' && !in_quotes) {
      cells.emplace_back();
    } else {
      cells.back() += ch;
    }
  }
  return cells;
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(HapstateStress, QuickSubsetConvergesOrRecordsAReason) {
  const fs::path dir =
      fs::temp_directory_path() / ("hapstate_stress_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const int code = run(std::string(HAPSTATE_STRESS_EXE) +
                       " --quick --no-retry --threads 2 --wall-cap 30 --out " + dir.string() +
                       " > " + (dir.string() + ".log") + " 2>&1");
  EXPECT_EQ(code, 0) << "see " << dir.string() << ".log";
  std::ifstream in(dir / "stress.csv");
  ASSERT_TRUE(in) << "no stress.csv";
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv(line);
  std::map<std::string, int> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = static_cast<int>(i);
  for (const char* name :
       {"law", "nu", "load", "step", "mesh", "probe", "status", "failure", "reason", "iterations",
        "max_force_N", "max_stretch", "min_stretch", "reached", "mesh_min_quality"})
    ASSERT_TRUE(col.count(name)) << name;
  std::map<std::string, std::vector<std::string>> rows;
  int cases = 0, converged = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> r = split_csv(line);
    ASSERT_EQ(r.size(), header.size()) << line;
    const std::string id = r[col["law"]] + "/nu" + r[col["nu"]] + "/" + r[col["load"]] + "/" +
                           r[col["step"]] + "/" + r[col["mesh"]] + "/" + r[col["probe"]];
    rows[id] = r;
    ++cases;
    const std::string& status = r[col["status"]];
    ASSERT_TRUE(status == "converged" || status == "failed")
        << id << ": " << status << " " << r[col["reason"]];
    if (status == "converged") {
      ++converged;
      EXPECT_EQ(r[col["reason"]], "") << id;
      EXPECT_DOUBLE_EQ(std::stod(r[col["reached"]]), 1.0) << id;
      for (const char* name : {"max_force_N", "max_stretch", "min_stretch"})
        EXPECT_TRUE(std::isfinite(std::stod(r[col[name]]))) << id << " " << name;
    } else {
      EXPECT_FALSE(r[col["reason"]].empty()) << id;
      EXPECT_FALSE(r[col["failure"]].empty()) << id;
    }
  }
  EXPECT_EQ(cases, static_cast<int>(stress_matrix(false).size()));
  // Cases known to converge (so that the test can fail): the linear law in one Newton step per
  // move plus the predictor; neo-Hooke stretched to >= 50 % and compressed by >= 30 % by the patch.
  auto get = [&](const std::string& id) -> const std::vector<std::string>& {
    static const std::vector<std::string> none;
    EXPECT_TRUE(rows.count(id)) << id;
    return rows.count(id) ? rows.at(id) : none;
  };
  const auto& linear = get("linear/nu0.3/stretch/grid/regular/patch");
  ASSERT_FALSE(linear.empty());
  EXPECT_EQ(linear[col["status"]], "converged");
  EXPECT_LE(std::stoi(linear[col["iterations"]]), 3 * 4);  // 4 moves
  const auto& stretch = get("neohooke/nu0.3/stretch/grid/regular/patch");
  ASSERT_FALSE(stretch.empty());
  EXPECT_EQ(stretch[col["status"]], "converged");
  EXPECT_GE(std::stod(stretch[col["max_stretch"]]), 1.5);
  const auto& compress = get("neohooke/nu0.3/compress/grid/regular/patch");
  ASSERT_FALSE(compress.empty());
  EXPECT_EQ(compress[col["status"]], "converged");
  EXPECT_LE(std::stod(compress[col["min_stretch"]]), 0.7);
  // The failure path: the quick subset holds cases that fail in the full matrix (StVK pressed past
  // its limit point, neo-Hooke at nu 0.4999 on a saddle of the locked mesh); at least one fails,
  // and every failed row names the solver's failure and its reason (checked above). If a solver
  // improvement makes them converge, pick other failing cases for the subset.
  int failed = 0;
  for (const char* id : {"stvk/nu0.4999/stretch/whole/sliver/node",
                         "neohooke/nu0.4999/compress/whole/regular/node"}) {
    const auto& r = get(id);
    ASSERT_FALSE(r.empty());
    failed += r[col["status"]] == "failed" ? 1 : 0;
  }
  EXPECT_GE(failed, 1);
  const auto& sliver = get("mooney/nu0.3/stretch/whole/sliver/patch");
  ASSERT_FALSE(sliver.empty());
  EXPECT_LT(std::stod(sliver[col["mesh_min_quality"]]), 0.1);
  EXPECT_GE(converged, cases / 2);
  // The Markdown report names its tables.
  std::ifstream md(dir / "stress.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("Converged per law and Poisson's ratio"), std::string::npos);
  EXPECT_NE(text.find("Failures"), std::string::npos);
  fs::remove_all(dir);
  fs::remove(dir.string() + ".log");
}

TEST(HapstateStress, BadOptionsExitTwo) {
  EXPECT_EQ(run(std::string(HAPSTATE_STRESS_EXE) + " --quick --full > /dev/null 2>&1"), 2);
  EXPECT_EQ(run(std::string(HAPSTATE_STRESS_EXE) +
                " --filter nosuchcase --out /tmp/x_stress_none > /dev/null 2>&1"),
            2);
}

}  // namespace
}  // namespace hapstate
