// Runs the real hapstate-solve executable (path from CMake) on the bundled liver scene the
// way a user would: exit codes, output files, and the messages of bad input.
#include "../common/scene_variant.h"
#include "io/probe_path.h"
#include "scene/bind.h"
#include "scene/scene.h"
#include "solver/path_solver.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace hapstate {
namespace {

namespace fs = std::filesystem;

const std::string kScene = HAPSTATE_SOURCE_DIR "/pipelines/liver/scene.toml";
const std::string kHeader =
    "step,x,y,z,fx,fy,fz,residual,iterations,substeps,cutbacks,wall_ms,status";
constexpr int kLiverNodes = 181;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

using test_util::slurp;

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> split(const std::string& line, char sep = ',') {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, sep);) cells.push_back(cell);
  return cells;
}

// A fresh, empty working folder per test, removed afterwards.
class HapstateSolve : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("hapstate_solve_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  struct Run {
    int exit_code = -1;
    std::string out, err;
  };
  // Runs hapstate-solve with `args` (each quoted), capturing stdout and stderr.
  Run solve(const std::vector<std::string>& args) {
    std::string cmd = quote(HAPSTATE_SOLVE_EXE);
    for (const auto& a : args) cmd.append(" ").append(quote(a));
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    cmd.append(" >").append(quote(out.string())).append(" 2>").append(quote(err.string()));
    cmd.append(" </dev/null");
    const int status = std::system(cmd.c_str());
    Run r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

Eigen::Vector3d liver_probe_rest() {
  static const Eigen::Vector3d rest = build_problem(load_scene(kScene)).probe_rest;
  return rest;
}

// The probe's target on the standard 3-point straight path: 0.5 cm up and 0.25 cm out.
Eigen::Vector3d straight_target() { return liver_probe_rest() + Eigen::Vector3d(-0.25, 0.0, 0.5); }

std::vector<std::string> straight_args() {
  const Eigen::Vector3d q = straight_target();
  char x[3][40];
  for (int c = 0; c < 3; ++c) std::snprintf(x[c], sizeof x[c], "%.17g", q[c]);
  return {kScene, "--straight", x[0], x[1], x[2], "--steps", "3", "-q"};
}

TEST_F(HapstateSolve, StraightPathWritesOneOkRowPerPoint) {
  auto args = straight_args();
  args.insert(args.end(), {"-o", p("out.csv")});
  const Run r = solve(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = lines_of(p("out.csv"));
  ASSERT_EQ(lines.size(), 4u) << slurp(p("out.csv"));
  EXPECT_EQ(lines[0], kHeader);

  // Reference: the same path solved in-process with the library.
  const Problem problem = build_problem(load_scene(kScene));
  PathSolver solver(problem);
  const ProbePath path = straight_path(problem.probe_rest, straight_target(), 3);
  for (int k = 0; k < 3; ++k) {
    const auto cells = split(lines[k + 1]);
    ASSERT_EQ(cells.size(), 13u) << lines[k + 1];
    EXPECT_EQ(std::stoi(cells[0]), k + 1);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(std::stod(cells[1 + c]), path[k][c], 1e-10) << lines[k + 1];
    EXPECT_EQ(cells[12], "ok") << lines[k + 1];
    EXPECT_GE(std::stoi(cells[8]), 1);     // iterations
    EXPECT_EQ(std::stoi(cells[9]), 1);     // substeps (fast: one, no cut-back)
    EXPECT_EQ(std::stoi(cells[10]), 0);    // cutbacks
    EXPECT_GE(std::stod(cells[11]), 0.0);  // wall_ms
    ASSERT_TRUE(solver.move_to(path[k] - problem.probe_rest).ok);
    const Eigen::Vector3d f = solver.force_felt();
    const Eigen::Vector3d f_csv(std::stod(cells[4]), std::stod(cells[5]), std::stod(cells[6]));
    // 12 significant digits in the CSV; the same deterministic solve.
    EXPECT_LE((f_csv - f).norm(), 1e-9 * f.norm()) << lines[k + 1] << "\n" << f.transpose();
    EXPECT_GT(f.norm(), 1e-3);
    EXPECT_LE(std::stod(cells[7]), 1e-7 * f.norm());  // residual
  }
}

// --rest (issue 40): the liver under its own weight, with no [probe] and no [grid]; the table
// holds the library's rest state, and a path from rest starts with zero force.
TEST_F(HapstateSolve, RestSolvesTheLoadedRestStateAlone) {
  std::string text = slurp(kScene);
  text = std::regex_replace(text, std::regex("file = \"[^\"]*\""),
                            "file = \"" HAPSTATE_SOURCE_DIR "/data/meshes/liver.msh\"");
  text = std::regex_replace(text, std::regex("poisson = 0.45"),
                            "poisson = 0.45\ndensity = 1000\n[loads]\ngravity = [0, -9.81, 0]");
  std::ofstream(p("gravity.toml")) << text;
  const std::string no_probe = text.substr(0, text.find("[probe]"));
  std::ofstream(p("rest_only.toml")) << no_probe;
  const Run r = solve({p("rest_only.toml"), "--rest", "-o", p("rest.csv"), "--vtu", p("vtu")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("loaded rest state: weight"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(p("vtu/rest.vtu")));
  const auto lines = lines_of(p("rest.csv"));
  ASSERT_EQ(lines.size(), kLiverNodes + 1u);
  EXPECT_EQ(lines[0], "node,x,y,z,ux,uy,uz");
  const Problem problem = build_problem(load_scene(p("gravity.toml")));
  ASSERT_EQ(problem.rest_m.size(), 3 * kLiverNodes);
  double largest = 0;
  for (int n = 0; n < kLiverNodes; ++n) {
    const auto cells = split(lines[n + 1]);
    ASSERT_EQ(cells.size(), 7u);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(std::stod(cells[4 + c]), problem.rest_m[3 * n + c] / problem.unit, 1e-9);
    largest = std::max(largest, problem.rest_m.segment<3>(3 * n).norm() / problem.unit);
  }
  EXPECT_GT(largest, 0.1);  // cm: the liver does sag
  // The scene with its probe: the first point of a path is the rest position, force zero.
  const Run path =
      solve({p("gravity.toml"), "--by", "0", "0", "0", "--steps", "1", "-q", "-o", p("path.csv")});
  ASSERT_EQ(path.exit_code, 0) << path.err;
  const auto row = split(lines_of(p("path.csv")).at(1));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(std::stod(row[4 + c]), 0.0, 1e-9);
  // A path needs the probe: without [probe] the scene is refused with the table named.
  const Run refused = solve({p("rest_only.toml"), "--by", "0", "0", "1", "-o", p("x.csv")});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("missing table [probe]"), std::string::npos) << refused.err;
}

TEST_F(HapstateSolve, MalformedPathNamesFileAndLine) {
  const std::string path = p("bad_path.csv");
  std::ofstream(path) << "x,y,z\n-2.5,3.5,2.3\n-2.5,3.x5,2.4\n-2.5,3.5,2.5\n";
  const Run r = solve({kScene, "--path", path, "-o", p("out.csv"), "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(path + ":3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3.x5"), std::string::npos) << r.err;
}

TEST_F(HapstateSolve, MissingSceneFails) {
  const std::string scene = p("no_such_scene.toml");
  const Run r = solve({scene, "--straight", "0", "0", "0", "-o", p("out.csv"), "-q"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no_such_scene.toml"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("out.csv")));
}

TEST_F(HapstateSolve, BadSceneNamesTheKey) {
  std::string text = slurp(kScene);
  // Absolute mesh path (the copy lives elsewhere) and an impossible Poisson ratio.
  const std::string mesh = HAPSTATE_SOURCE_DIR "/data/meshes/liver.msh";
  text = std::regex_replace(text, std::regex(R"(file = "[^"]*")"), "file = \"" + mesh + "\"");
  text = std::regex_replace(text, std::regex(R"(poisson = 0\.45)"), "poisson = 0.7");
  ASSERT_NE(text.find("poisson = 0.7"), std::string::npos);
  ASSERT_NE(text.find(mesh), std::string::npos);
  const std::string scene = p("bad.toml");
  std::ofstream(scene) << text;
  const Run r = solve({scene, "--straight", "0", "0", "0", "-o", p("out.csv"), "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("material.poisson"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.toml:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("out.csv")));
}

TEST_F(HapstateSolve, VtuWritesOneFilePerStepAndCollection) {
  auto args = straight_args();
  args.insert(args.end(), {"-o", p("out.csv"), "--vtu", p("vtu")});
  const Run r = solve(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"step_00001.vtu", "step_00002.vtu", "step_00003.vtu", "path.pvd"})
    EXPECT_TRUE(fs::is_regular_file(dir_ / "vtu" / name)) << name;
  EXPECT_FALSE(fs::exists(dir_ / "vtu" / "step_00004.vtu"));
  const std::string vtu = slurp(dir_ / "vtu" / "step_00001.vtu");
  EXPECT_NE(vtu.find("NumberOfPoints=\"181\""), std::string::npos) << vtu.substr(0, 400);
  EXPECT_NE(vtu.find("NumberOfCells=\"596\""), std::string::npos) << vtu.substr(0, 400);
  const std::string pvd = slurp(dir_ / "vtu" / "path.pvd");
  for (const char* name : {"step_00001.vtu", "step_00002.vtu", "step_00003.vtu"})
    EXPECT_NE(pvd.find(name), std::string::npos) << pvd;
}

TEST_F(HapstateSolve, DisplacementsHaveOneRowPerNodeAndStep) {
  auto args = straight_args();
  args.insert(args.end(), {"-o", p("out.csv"), "--displacements", p("u.csv")});
  const Run r = solve(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = lines_of(p("u.csv"));
  ASSERT_EQ(lines.size(), 1u + 3 * kLiverNodes);
  EXPECT_EQ(lines[0], "step,node,ux,uy,uz");
  const Problem problem = build_problem(load_scene(kScene));
  const int grabbed = problem.constraints.probe_nodes.at(0);
  const ProbePath path = straight_path(problem.probe_rest, straight_target(), 3);
  for (int k = 0; k < 3; ++k) {
    for (int n = 0; n < kLiverNodes; ++n) {
      const auto cells = split(lines[1 + k * kLiverNodes + n]);
      ASSERT_EQ(cells.size(), 5u);
      EXPECT_EQ(std::stoi(cells[0]), k + 1);
      EXPECT_EQ(std::stoi(cells[1]), n);
      const Eigen::Vector3d u(std::stod(cells[2]), std::stod(cells[3]), std::stod(cells[4]));
      // The grabbed node follows the probe; the fixed ligament nodes stay put.
      if (n == grabbed) {
        EXPECT_LE((u - (path[k] - problem.probe_rest)).norm(), 1e-10) << k;
      }
      bool fixed = true;
      for (int c = 0; c < 3; ++c) fixed &= problem.constraints.role[3 * n + c] == DofRole::kFixed;
      if (fixed) {
        EXPECT_EQ(u, Eigen::Vector3d::Zero()) << "node " << n;
      }
    }
  }
}

TEST_F(HapstateSolve, ExportCcxWritesDeck) {
  auto args = straight_args();
  args.insert(args.end(), {"--export-ccx", p("ccx")});
  const Run r = solve(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path deck = dir_ / "ccx" / "problem.inp";
  ASSERT_TRUE(fs::is_regular_file(deck));
  const std::string inp = slurp(deck);
  EXPECT_NE(inp.find("*NODE"), std::string::npos);
  EXPECT_NE(inp.find("*ELEMENT, TYPE=C3D4"), std::string::npos);
  EXPECT_NE(inp.find("*HYPERELASTIC, NEO HOOKE"), std::string::npos);
  // One *STEP per path point.
  std::size_t steps = 0;
  for (std::size_t at = inp.find("*STEP"); at != std::string::npos; at = inp.find("*STEP", at + 1))
    ++steps;
  EXPECT_EQ(steps, 3u);
  EXPECT_FALSE(fs::exists(p("out.csv")));
}

}  // namespace
}  // namespace hapstate

namespace hapstate {
namespace {

const std::string kContactHeader = kHeader + ",touched,active_set_changes";

// Rows of a contact run: (z, fz, status, touched).
struct ContactRow {
  double z, fx, fy, fz;
  std::string status;
  int touched;
};
std::vector<ContactRow> contact_rows(const fs::path& csv) {
  std::vector<ContactRow> rows;
  const auto lines = lines_of(csv);
  for (std::size_t k = 1; k < lines.size(); ++k) {
    const auto c = split(lines[k]);
    if (c.size() != 15u) return {};
    rows.push_back({std::stod(c[3]), std::stod(c[4]), std::stod(c[5]), std::stod(c[6]), c[12],
                    std::stoi(c[13])});
  }
  return rows;
}

// The bundled plate scene through the real tool: reaching the centre (2, 2, 0.2) from below
// (straight up from rest) and from above (around the plate's edge, then down) gives opposite
// normal forces; untouched rows are exactly zero.
TEST_F(HapstateSolve, ContactPlateFromBelowAndFromAbove) {
  const Run below = solve({test_util::plate_variant(dir_, {}), "--straight", "2", "2", "0.2",
                           "--steps", "12", "-q", "-o", p("below.csv")});
  ASSERT_EQ(below.exit_code, 0) << below.err;
  EXPECT_EQ(lines_of(p("below.csv"))[0], kContactHeader);
  {
    std::ofstream path(p("above.txt"));
    path << "x,y,z\n2,2,-1.5\n5,2,-1.5\n5,2,1.5\n2,2,1.5\n";
    for (double z = 1.3; z > 0.25; z -= 0.2) path << "2,2," << z << "\n";
    path << "2,2,0.2\n";
  }
  const Run above = solve(
      {test_util::plate_variant(dir_, {}), "--path", p("above.txt"), "-q", "-o", p("above.csv")});
  ASSERT_EQ(above.exit_code, 0) << above.err;
  const auto b = contact_rows(p("below.csv"));
  const auto a = contact_rows(p("above.csv"));
  ASSERT_EQ(b.size(), 12u);
  ASSERT_EQ(a.size(), 11u);
  for (const auto* rows : {&a, &b})
    for (const ContactRow& r : *rows) {
      EXPECT_EQ(r.status, "ok");
      if (r.touched == 0) {
        EXPECT_EQ(r.fx, 0.0);
        EXPECT_EQ(r.fy, 0.0);
        EXPECT_EQ(r.fz, 0.0);
      }
    }
  // First touch from below: the sphere's top (z + 0.8) passes the plate's bottom face at -0.1.
  EXPECT_EQ(b[0].touched, 0);  // z = -0.9: top at -0.1, not inside
  EXPECT_GT(b[1].touched, 0);  // z = -0.8
  EXPECT_EQ(a[4].touched, 0);  // z = 1.3: bottom at 0.5, clear of the top face at 0.1
  EXPECT_GT(a.back().touched, 0);
  EXPECT_LT(b.back().fz, -0.1);  // pushed up from below: the plate pushes the probe down
  EXPECT_GT(a.back().fz, 0.1);   // pushed down from above: it pushes the probe up
}

// The bundled liver touched by a sphere: pressed 1 cm along minus the surface normal at the
// touched spot, it converges, touches, and the force pushes back out of the liver.
TEST_F(HapstateSolve, ContactLiverPressedConvergesAndPushesBack) {
  const std::string scene = HAPSTATE_SOURCE_DIR "/pipelines/liver-contact/scene.toml";
  const Run r =
      solve({scene, "--by", "0.18", "-0.4", "-0.9", "--steps", "5", "-q", "-o", p("liver.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = contact_rows(p("liver.csv"));
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0].touched, 0);  // 0.2 cm of the 0.25 cm gap: not yet
  EXPECT_GT(rows.back().touched, 0);
  const Eigen::Vector3d normal(-0.18, 0.40, 0.90);  // outward normal at node 100
  const Eigen::Vector3d f(rows.back().fx, rows.back().fy, rows.back().fz);
  EXPECT_GT(f.dot(normal.normalized()), 0.0) << f.transpose();
}

TEST_F(HapstateSolve, ContactProbeCannotBeExportedToCalculix) {
  const Run r =
      solve({test_util::plate_variant(dir_, {}), "--by", "0", "0", "1", "--export-ccx", p("ccx")});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--export-ccx: a contact probe cannot be exported"), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace hapstate
