// parse_scene / load_scene: values, defaults and every kind of validation message.
#include "scene/scene.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <regex>

namespace hapstate {
namespace {

using testing::error_of;
using testing::replace_once;
using testing::ScratchDir;

// Line numbers matter: the expected messages below refer to them.
const std::string kBase =
    "[mesh]\n"                                     // 1
    "file = \"box.msh\"\n"                         // 2
    "unit = 0.01\n"                                // 3
    "\n"                                           // 4
    "[material]\n"                                 // 5
    "law = \"neohooke\"\n"                         // 6
    "young = 5000.0\n"                             // 7
    "poisson = 0.45\n"                             // 8
    "\n"                                           // 9
    "[[fixed]]\n"                                  // 10
    "box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]\n"  // 11
    "\n"                                           // 12
    "[probe]\n"                                    // 13
    "point = [-2.0, 4.0, 1.0]\n"                   // 14
    "max_force = 3.0\n"                            // 15
    "\n"                                           // 16
    "[grid]\n"                                     // 17
    "spacing = 0.25\n"                             // 18
    "\n"                                           // 19
    "[solver]\n"                                   // 20
    "substeps = 4\n"                               // 21
    "tolerance = 1e-8\n"                           // 22
    "max_iterations = 30\n";                       // 23

class ParseScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_.write("box.msh", "not read by the parser\n");
    dir_.write("fixed.txt", "0 1 2\n");
    dir_.write("grab.txt", "7\n");
    scene_path_ = dir_.path() / "scene.toml";
  }
  Scene parse(const std::string& text) const { return parse_scene(text, scene_path_); }
  std::string error(const std::string& text) const {
    return error_of([&] { parse(text); });
  }
  // "<scene path>:LINE: message"
  std::string at(int line, const std::string& message) const {
    return scene_path_.string() + ":" + std::to_string(line) + ": " + message;
  }

  ScratchDir dir_;
  std::filesystem::path scene_path_;
};

TEST_F(ParseScene, BaseSceneValues) {
  const Scene s = parse(kBase);
  EXPECT_EQ(s.path, scene_path_);
  EXPECT_EQ(s.text, kBase);
  EXPECT_EQ(s.mesh.file, dir_.path() / "box.msh");
  EXPECT_DOUBLE_EQ(s.mesh.unit, 0.01);
  EXPECT_EQ(s.material.law, Law::kNeoHooke);
  EXPECT_EQ(s.material.young, 5000.0);
  EXPECT_EQ(s.material.poisson, 0.45);
  EXPECT_FALSE(s.material.c10 || s.material.d1 || s.material.mu || s.material.lambda);
  ASSERT_EQ(s.fixed.size(), 1u);
  const auto* box = std::get_if<BoxSelector>(&s.fixed[0].where);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->box.min, Eigen::Vector3d(0, 3, -1));
  EXPECT_EQ(box->box.max, Eigen::Vector3d(2, 5, 2));
  EXPECT_EQ(s.fixed[0].dofs, (DofMask{true, true, true}));
  EXPECT_EQ(s.fixed[0].line, 10);
  EXPECT_EQ(s.probe.mode, ProbeMode::kGrab);
  EXPECT_EQ(s.probe.point, Eigen::Vector3d(-2, 4, 1));
  EXPECT_FALSE(s.probe.radius);
  EXPECT_FALSE(s.probe.nodes_file);
  EXPECT_EQ(s.probe.dofs, (DofMask{true, true, true}));
  EXPECT_EQ(s.probe.max_force, 3.0);
  EXPECT_EQ(s.probe.line, 13);
  EXPECT_EQ(s.grid.spacing, Eigen::Vector3d::Constant(0.25));
  EXPECT_FALSE(s.grid.dims);
  EXPECT_FALSE(s.grid.box);
  EXPECT_EQ(s.solver.substeps, 4);
  EXPECT_EQ(s.solver.tolerance, 1e-8);
  EXPECT_EQ(s.solver.max_iterations, 30);
}

TEST_F(ParseScene, DefaultsOfOptionalKeys) {
  const std::string text =
      "[mesh]\nfile = \"box.msh\"\n"
      "[material]\nlaw = \"stvk\"\nmu = 1000\nlambda = 4000\n"
      "[probe]\nnodes = \"grab.txt\"\nmax_force = 2\n"
      "[grid]\nspacing = 0.5\n";
  const Scene s = parse(text);
  EXPECT_EQ(s.mesh.unit, 1.0);
  EXPECT_EQ(s.material.law, Law::kStvk);
  EXPECT_EQ(s.material.mu, 1000.0);
  EXPECT_EQ(s.material.lambda, 4000.0);
  EXPECT_FALSE(s.material.young || s.material.poisson);
  EXPECT_TRUE(s.fixed.empty());
  EXPECT_EQ(s.probe.mode, ProbeMode::kGrab);
  EXPECT_EQ(s.probe.nodes_file, dir_.path() / "grab.txt");
  EXPECT_FALSE(s.probe.point);
  EXPECT_EQ(s.probe.dofs, (DofMask{true, true, true}));
  const SolverOptions defaults;
  EXPECT_EQ(s.solver.substeps, defaults.substeps);
  EXPECT_EQ(s.solver.tolerance, defaults.tolerance);
  EXPECT_EQ(s.solver.absolute_tolerance, defaults.absolute_tolerance);
  EXPECT_EQ(s.solver.max_iterations, defaults.max_iterations);
  EXPECT_EQ(s.solver.max_cutbacks, defaults.max_cutbacks);
  EXPECT_FALSE(s.levels.displacement_tolerance);
  EXPECT_FALSE(s.levels.force_tolerance);
  const LevelTolerances t = level_tolerances(s);
  EXPECT_DOUBLE_EQ(t.displacement, 0.005);  // 1 % of the spacing
  EXPECT_DOUBLE_EQ(t.force, 0.02);          // 1 % of max_force
}

TEST_F(ParseScene, EverySelectorAndOptionalTable) {
  const std::string text =
      "[mesh]\nfile = \"box.msh\"\n"
      "[material]\nlaw = \"mooney\"\nc10 = 400\nc01 = 100\nd1 = 1e-3\n"
      "[[fixed]]\nplane = { point = [0, 0, 0], normal = [0, 0, 2], tolerance = 0.1 }\n"
      "dofs = \"z\"\n"
      "[[fixed]]\nplane = { point = [1, 0, 0], normal = [1, 0, 0] }\n"
      "[[fixed]]\ngroup = \"base\"\ndofs = \"yx\"\n"
      "[[fixed]]\nnodes = \"fixed.txt\"\n"
      "[probe]\npoint = [1, 2, 3]\nradius = 0.5\ndofs = \"xz\"\nmax_force = 1.5\n"
      "[grid]\ndims = [5, 6, 7]\nbox = [[0, 0, 0], [4, 10, 3]]\n"
      "[solver]\nabsolute_tolerance = 1e-9\nmax_cutbacks = 3\n"
      "[levels]\ndisplacement_tolerance = 0.01\nforce_tolerance = 0.05\n"
      "[certify]\npaths = 40\nsteps = 25\n";
  const Scene s = parse(text);
  EXPECT_EQ(s.certify.paths, 40);
  EXPECT_EQ(s.certify.steps, 25);
  EXPECT_EQ(s.material.c10, 400.0);
  EXPECT_EQ(s.material.c01, 100.0);
  EXPECT_EQ(s.material.d1, 1e-3);
  ASSERT_EQ(s.fixed.size(), 4u);
  const auto& plane = std::get<PlaneSelector>(s.fixed[0].where);
  EXPECT_EQ(plane.normal, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(plane.tolerance, 0.1);
  EXPECT_EQ(s.fixed[0].dofs, (DofMask{false, false, true}));
  EXPECT_FALSE(std::get<PlaneSelector>(s.fixed[1].where).tolerance);
  EXPECT_EQ(std::get<PlaneSelector>(s.fixed[1].where).point, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(std::get<GroupSelector>(s.fixed[2].where).name, "base");
  EXPECT_EQ(s.fixed[2].dofs, (DofMask{true, true, false}));
  EXPECT_EQ(std::get<NodesSelector>(s.fixed[3].where).file, dir_.path() / "fixed.txt");
  EXPECT_EQ(s.probe.radius, 0.5);
  EXPECT_EQ(s.probe.dofs, (DofMask{true, false, true}));
  EXPECT_EQ(s.grid.dims, (std::array<int, 3>{5, 6, 7}));
  EXPECT_EQ(s.grid.box->max, Eigen::Vector3d(4, 10, 3));
  EXPECT_DOUBLE_EQ(smallest_grid_spacing(s.grid), 0.5);  // 3 / (7 - 1)
  EXPECT_EQ(s.solver.absolute_tolerance, 1e-9);
  EXPECT_EQ(s.solver.max_cutbacks, 3);
  EXPECT_EQ(s.solver.substeps, SolverOptions{}.substeps);
  EXPECT_EQ(level_tolerances(s).displacement, 0.01);
  EXPECT_EQ(level_tolerances(s).force, 0.05);
}

TEST_F(ParseScene, GridSpacingPerAxisAndContactProbe) {
  std::string text = replace_once(kBase, "spacing = 0.25", "spacing = [0.5, 0.25, 1]");
  text = replace_once(text, "point = [-2.0, 4.0, 1.0]",
                      "mode = \"contact\"\npoint = [-2.0, 4.0, 1.0]\nradius = 0.3");
  const Scene s = parse(text);
  EXPECT_EQ(s.grid.spacing, Eigen::Vector3d(0.5, 0.25, 1));
  EXPECT_EQ(s.probe.mode, ProbeMode::kContact);
  EXPECT_EQ(s.probe.radius, 0.3);
  EXPECT_EQ(s.probe.friction, Friction::kNone);  // frictionless sliding by default
  EXPECT_FALSE(s.grid.refine_depth);             // unset: the refine stage's default_refine_depth
  EXPECT_EQ(parse(replace_once(text, "spacing = [0.5, 0.25, 1]",
                               "spacing = [0.5, 0.25, 1]\nrefine_depth = 1"))
                .grid.refine_depth,
            1);
  EXPECT_EQ(parse(replace_once(text, "radius = 0.3", "radius = 0.3\nfriction = \"stick\""))
                .probe.friction,
            Friction::kStick);
}

// One replacement in the base scene -> exactly one problem at `line`.
struct BadCase {
  std::string from, to;
  int line;
  std::string message;
};

class BadValue : public ParseScene, public ::testing::WithParamInterface<BadCase> {};

TEST_P(BadValue, ReportsOneLocatedProblem) {
  const BadCase& c = GetParam();
  EXPECT_EQ(error(replace_once(kBase, c.from, c.to)), at(c.line, c.message));
}

INSTANTIATE_TEST_SUITE_P(
    Scene, BadValue,
    ::testing::Values(
        BadCase{"unit = 0.01", "unit = 0", 3, "key 'mesh.unit' = 0: must be > 0"},
        BadCase{"unit = 0.01", "unit = \"cm\"", 3,
                "key 'mesh.unit' = \"cm\": expected a number, got a string"},
        BadCase{"unit = 0.01", "unit = nan", 3, "key 'mesh.unit' = nan: must be a finite number"},
        BadCase{"file = \"box.msh\"", "file = 3", 2,
                "key 'mesh.file' = 3: expected a string, got an integer"},
        BadCase{"law = \"neohooke\"", "law = \"neohook\"", 6,
                "key 'material.law' = \"neohook\": must be one of linear, stvk, neohooke, mooney"},
        BadCase{"young = 5000.0", "young = -5", 7, "key 'material.young' = -5: must be > 0"},
        BadCase{"poisson = 0.45", "poisson = 0.7", 8,
                "key 'material.poisson' = 0.7: must be in (-1, 0.5)"},
        BadCase{"poisson = 0.45", "poisson = 0.5", 8,
                "key 'material.poisson' = 0.5: must be in (-1, 0.5)"},
        BadCase{"poisson = 0.45", "poisson = -1", 8,
                "key 'material.poisson' = -1: must be in (-1, 0.5)"},
        BadCase{"box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]",
                "box = [[0.0, 3.0, 2.0], [2.0, 5.0, -1.0]]", 11,
                "key 'fixed[0].box' = [[0.0, 3.0, 2.0], [2.0, 5.0, -1.0]]: min must be < max in "
                "every component (z: 2 >= -1)"},
        BadCase{"box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]", "box = [0, 1]", 11,
                "key 'fixed[0].box' = [0, 1]: min corner: expected an array of 3 numbers "
                "[x, y, z], got an integer"},
        BadCase{"box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]",
                "plane = { point = [0, 0, 0], normal = [0, 0, 0] }", 11,
                "key 'fixed[0].plane.normal' = [0, 0, 0]: must be non-zero"},
        BadCase{"box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]",
                "plane = { point = [0, 0, 0], normal = [0, 0, 1], tolerance = 0 }", 11,
                "key 'fixed[0].plane.tolerance' = 0: must be > 0"},
        BadCase{"box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]", "group = \"\"", 11,
                "key 'fixed[0].group' = \"\": must name a physical group of the mesh"},
        BadCase{"[[fixed]]\n", "[[fixed]]\ndofs = \"xx\"\n", 11,
                "key 'fixed[0].dofs' = \"xx\": component 'x' repeated"},
        BadCase{"[[fixed]]\n", "[[fixed]]\ndofs = \"xw\"\n", 11,
                "key 'fixed[0].dofs' = \"xw\": 'w' is not a component; use letters from \"xyz\""},
        BadCase{"[[fixed]]\n", "[[fixed]]\ndofs = \"\"\n", 11,
                "key 'fixed[0].dofs' = \"\": must name at least one of x, y, z"},
        BadCase{"point = [-2.0, 4.0, 1.0]", "point = [-2.0, 4.0]", 14,
                "key 'probe.point' = [-2.0, 4.0]: expected an array of 3 numbers [x, y, z], got "
                "an array of 2 element(s)"},
        BadCase{"point = [-2.0, 4.0, 1.0]", "point = [-2.0, \"4\", 1.0]", 14,
                "key 'probe.point' = [-2.0, \"4\", 1.0]: element 1: expected a number, got a "
                "string"},
        BadCase{"point = [-2.0, 4.0, 1.0]", "point = [-2.0, 4.0, 1.0]\nradius = -0.1", 15,
                "key 'probe.radius' = -0.1: must be > 0"},
        BadCase{"point = [-2.0, 4.0, 1.0]", "point = [-2.0, 4.0, 1.0]\nmode = \"poke\"", 15,
                "key 'probe.mode' = \"poke\": must be one of grab, contact"},
        BadCase{"max_force = 3.0", "max_force = 0.0", 15,
                "key 'probe.max_force' = 0.0: must be > 0"},
        BadCase{"spacing = 0.25", "spacing = -0.25", 18, "key 'grid.spacing' = -0.25: must be > 0"},
        BadCase{"spacing = 0.25", "spacing = 0.25\nrefine_depth = 4", 19,
                "key 'grid.refine_depth' = 4: must be in [1, 3]"},
        BadCase{"spacing = 0.25", "spacing = [0.25, 0.0, 0.25]", 18,
                "key 'grid.spacing' = [0.25, 0.0, 0.25]: every component must be > 0"},
        BadCase{"spacing = 0.25", "dims = [1, 4, 4]\nbox = [[0, 0, 0], [1, 1, 1]]", 18,
                "key 'grid.dims' = [1, 4, 4]: every count must be in [2, 1000000]"},
        BadCase{"spacing = 0.25", "dims = [3, 4.0, 4]\nbox = [[0, 0, 0], [1, 1, 1]]", 18,
                "key 'grid.dims' = [3, 4.0, 4]: expected an array of 3 integers [nx, ny, nz], got "
                "an array of 3 element(s) or non-integers"},
        BadCase{"substeps = 4", "substeps = 0", 21,
                "key 'solver.substeps' = 0: must be in [1, 10000]"},
        BadCase{"substeps = 4", "substeps = 4.5", 21,
                "key 'solver.substeps' = 4.5: expected an integer, got a floating-point number"},
        BadCase{"tolerance = 1e-8", "tolerance = 0", 22,
                "key 'solver.tolerance' = 0: must be in (0, 1)"},
        BadCase{"max_iterations = 30", "max_iterations = 2000", 23,
                "key 'solver.max_iterations' = 2000: must be in [1, 1000]"},
        BadCase{"max_iterations = 30", "max_iterations = 30\nmax_cutbacks = -1", 24,
                "key 'solver.max_cutbacks' = -1: must be in [0, 50]"},
        BadCase{"max_iterations = 30", "max_iterations = 30\n[levels]\nforce_tolerance = 0", 25,
                "key 'levels.force_tolerance' = 0: must be > 0"},
        BadCase{"max_iterations = 30", "max_iterations = 30\n[certify]\npaths = 0", 25,
                "key 'certify.paths' = 0: must be in [1, 100000]"},
        BadCase{"max_iterations = 30", "max_iterations = 30\n[certify]\nsteps = 1", 25,
                "key 'certify.steps' = 1: must be in [2, 100000]"},
        BadCase{"max_iterations = 30", "max_iterations = 30\n[certify]\nseeds = 3", 25,
                "unknown key 'certify.seeds' (did you mean 'steps'?); allowed: paths, steps"},
        // Gravity, density and supports (issue 40).
        BadCase{"poisson = 0.45", "poisson = 0.45\ndensity = -1000", 9,
                "key 'material.density' = -1000: must be > 0"},
        BadCase{"poisson = 0.45", "poisson = 0.45\ndensity = 1000\n[loads]\ngravity = [0, nan, 0]",
                11, "key 'loads.gravity' = [0, nan, 0]: element 1: must be a finite number"},
        BadCase{"poisson = 0.45", "poisson = 0.45\n[loads]\ngravity = [0, 0, -9.81]", 9,
                "key 'loads.gravity' needs 'material.density' (kg/m^3): the body's weight is "
                "density x volume x gravity"},
        BadCase{"poisson = 0.45", "poisson = 0.45\ndensity = 1000\n[loads]\ngravity = [0, 0, 0]",
                11,
                "key 'loads.gravity' = [0, 0, 0]: must be non-zero (leave [loads] out for a body "
                "without weight)"},
        BadCase{"poisson = 0.45", "poisson = 0.45\ndensity = 1000\n[loads]\ngravity = -9.81", 11,
                "key 'loads.gravity' = -9.81: expected an array of 3 numbers [x, y, z], got a "
                "floating-point number"},
        BadCase{"[[fixed]]\n",
                "[[support]]\nbox = [[0, 0, 0], [1, 1, 1]]\nstiffness = -5\n[[fixed]]\n", 12,
                "key 'support[0].stiffness' = -5: must be > 0"},
        BadCase{"[[fixed]]\n", "[[support]]\nbox = [[0, 0, 0], [1, 1, 1]]\n[[fixed]]\n", 10,
                "missing key 'support[0].stiffness' (N/m^3, the supporting pressure per metre of "
                "displacement)"}));

TEST_F(ParseScene, UnknownKeyIsNamedWithSuggestion) {
  EXPECT_EQ(error(replace_once(kBase, "poisson = 0.45", "poisson = 0.45\npoison = 0.3")),
            at(9,
               "unknown key 'material.poison' (did you mean 'poisson'?); allowed: law, young, "
               "poisson, mu, lambda, c10, c01, d1, density"));
  EXPECT_EQ(error(replace_once(kBase, "[[fixed]]\n", "[[fixed]]\ncolour = \"red\"\n")),
            at(11, "unknown key 'fixed[0].colour'; allowed: box, plane, group, nodes, dofs"));
  EXPECT_EQ(error(replace_once(kBase, "box = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]",
                               "plane = { point = [0, 0, 0], normal = [0, 0, 1], tol = 1 }")),
            at(11, "unknown key 'fixed[0].plane.tol'; allowed: point, normal, tolerance"));
}

TEST_F(ParseScene, AMisspeltKeyIsNamedBeforeTheKeyItLeavesMissing) {
  // The misspelling (line 7) is the cause; the correct spelling's absence (reported at the
  // table's header, line 5) follows from it.
  EXPECT_EQ(error(replace_once(kBase, "young = 5000.0", "yung = 5000.0")),
            at(7,
               "unknown key 'material.yung' (did you mean 'young'?); allowed: law, young, "
               "poisson, mu, lambda, c10, c01, d1, density") +
                "\n" + at(5, "missing key 'material.young' (young and poisson go together)"));
}

TEST_F(ParseScene, UnknownTableIsNamed) {
  EXPECT_EQ(error(kBase + "[solvr]\nsubsteps = 2\n"),
            at(24,
               "unknown table 'solvr' (did you mean 'solver'?); allowed: mesh, material, "
               "fixed, support, loads, probe, grid, solver, levels, certify"));
  EXPECT_EQ(error("substeps = 2\n" + kBase),
            at(1,
               "unknown key 'substeps'; allowed: mesh, material, fixed, support, loads, probe, "
               "grid, solver, levels, certify"));
}

TEST_F(ParseScene, WrongTableShapes) {
  EXPECT_EQ(error(replace_once(kBase, "[[fixed]]", "[fixed]")),
            at(10,
               "key 'fixed' = {...}: expected an array of tables ([[fixed]] headers), got a "
               "table"));
  EXPECT_EQ(error(replace_once(kBase, "[probe]", "[[probe]]")),
            at(13, "key 'probe' = [{...}]: expected a table, got an array"));
}

TEST_F(ParseScene, MissingRequiredKeysAndTables) {
  EXPECT_EQ(error(replace_once(kBase, "law = \"neohooke\"\n", "")),
            at(5, "missing key 'material.law' (linear, stvk, neohooke or mooney)"));
  EXPECT_EQ(error(replace_once(kBase, "max_force = 3.0\n", "")),
            at(13, "missing key 'probe.max_force' (N, the device force limit)"));
  EXPECT_EQ(error(replace_once(kBase, "file = \"box.msh\"\n", "")),
            at(1, "missing key 'mesh.file'"));
  EXPECT_EQ(error(replace_once(kBase, "poisson = 0.45\n", "")),
            at(5, "missing key 'material.poisson' (young and poisson go together)"));
  EXPECT_EQ(
      error(replace_once(kBase, "point = [-2.0, 4.0, 1.0]\n", "")),
      at(13, "missing key 'probe.point' (grab needs point, point and radius, nodes, or group)"));
  EXPECT_EQ(error(replace_once(kBase, "spacing = 0.25\n", "")),
            at(17, "missing key 'grid.spacing' (or dims)"));
  EXPECT_EQ(error(replace_once(kBase, "spacing = 0.25", "dims = [3, 3, 3]")),
            at(17, "missing key 'grid.box' (required with dims)"));
  EXPECT_EQ(error(replace_once(kBase, "[probe]\npoint = [-2.0, 4.0, 1.0]\nmax_force = 3.0\n", "")),
            scene_path_.string() + ": missing table [probe]");
  EXPECT_EQ(error(replace_once(kBase, "young = 5000.0\npoisson = 0.45\n", "")),
            at(5,
               "missing material constants in [material]: give young and poisson, or c10 "
               "and d1"));
}

TEST_F(ParseScene, MaterialConstantsMustMatchTheLaw) {
  EXPECT_EQ(error(replace_once(kBase, "young = 5000.0\npoisson = 0.45", "mu = 1000\nd1 = 1e-3")),
            at(5, "missing key 'material.c10' (law 'neohooke' needs c10 and d1)") + "\n" +
                at(7,
                   "key 'material.mu' = 1000: does not apply to law 'neohooke' (give young and "
                   "poisson, or c10 and d1)"));
  EXPECT_EQ(error(replace_once(kBase, "poisson = 0.45", "poisson = 0.45\nc10 = 400")),
            at(9,
               "key 'material.c10' = 400: cannot be combined with young/poisson (give young "
               "and poisson, or c10 and d1)"));
  EXPECT_EQ(error(replace_once(kBase, "law = \"neohooke\"\nyoung = 5000.0\npoisson = 0.45",
                               "law = \"stvk\"\nmu = 1000\nlambda = -1000")),
            at(8, "key 'material.lambda' = -1000: must be > -2/3 mu (a positive bulk modulus)"));
  EXPECT_EQ(error(replace_once(kBase, "law = \"neohooke\"\nyoung = 5000.0\npoisson = 0.45",
                               "law = \"mooney\"\nc10 = 400\nc01 = -1\nd1 = 1e-3")),
            at(8, "key 'material.c01' = -1: must be >= 0"));
  // A negative lambda with a positive bulk modulus (nu < 0) is valid.
  EXPECT_NO_THROW(parse(replace_once(kBase, "law = \"neohooke\"\nyoung = 5000.0\npoisson = 0.45",
                                     "law = \"stvk\"\nmu = 1000\nlambda = -600")));
}

TEST_F(ParseScene, TwoAlternativesGiven) {
  EXPECT_EQ(error(replace_once(kBase, "[[fixed]]\n", "[[fixed]]\ngroup = \"base\"\n")),
            at(10,
               "[[fixed]] table 'fixed[0]': give exactly one of box, plane, group, nodes "
               "(got box and group)"));
  EXPECT_EQ(error(replace_once(kBase, "[[fixed]]\nbox = [[0.0, 3.0, -1.0], [2.0, 5.0, 2.0]]\n",
                               "[[fixed]]\ndofs = \"x\"\n")),
            at(10, "[[fixed]] table 'fixed[0]': give exactly one of box, plane, group, nodes"));
  EXPECT_EQ(error(replace_once(kBase, "max_force = 3.0", "max_force = 3.0\nnodes = \"grab.txt\"")),
            at(16,
               "key 'probe.nodes' = \"grab.txt\": give exactly one of point (with an "
               "optional radius), nodes or group"));
  EXPECT_EQ(error(replace_once(kBase, "max_force = 3.0", "max_force = 3.0\ngroup = \"tip\"")),
            at(16,
               "key 'probe.group' = \"tip\": give exactly one of point (with an "
               "optional radius), nodes or group"));
  EXPECT_EQ(error(replace_once(kBase, "spacing = 0.25",
                               "spacing = 0.25\ndims = [3, 3, 3]\nbox = [[0, 0, 0], [1, 1, 1]]")),
            at(19, "key 'grid.dims' = [3, 3, 3]: give either spacing or dims, not both"));
}

TEST_F(ParseScene, ContactProbeKeys) {
  const std::string contact = replace_once(kBase, "point = [-2.0, 4.0, 1.0]",
                                           "mode = \"contact\"\npoint = [-2.0, 4.0, 1.0]");
  EXPECT_EQ(error(contact), at(13, "missing key 'probe.radius' (contact: the sphere radius)"));
  EXPECT_EQ(error(replace_once(contact, "max_force = 3.0",
                               "max_force = 3.0\nradius = 1\n"
                               "dofs = \"x\"")),
            at(18, "key 'probe.dofs' = \"x\": only allowed with mode = \"grab\""));
  EXPECT_EQ(error(replace_once(contact, "max_force = 3.0",
                               "max_force = 3.0\nradius = 1\n"
                               "friction = \"coulomb\"")),
            at(18,
               "key 'probe.friction' = \"coulomb\": must be one of none (frictionless "
               "sliding), stick"));
  EXPECT_EQ(error(replace_once(kBase, "max_force = 3.0", "max_force = 3.0\nfriction = \"none\"")),
            at(16, "key 'probe.friction' = \"none\": only allowed with mode = \"contact\""));
}

TEST_F(ParseScene, MissingFilesAreReportedUnlessDisabled) {
  const std::string text = replace_once(kBase, "file = \"box.msh\"", "file = \"sub/none.msh\"");
  EXPECT_EQ(error(text), at(2, "key 'mesh.file' = \"sub/none.msh\": file not found: " +
                                   (dir_.path() / "sub/none.msh").string()));
  const Scene s = parse_scene(text, scene_path_, SceneParseOptions{.check_files = false});
  EXPECT_EQ(s.mesh.file, dir_.path() / "sub" / "none.msh");
}

TEST_F(ParseScene, AbsoluteFileNamesAreKept) {
  const auto mesh = dir_.path() / "box.msh";
  const Scene s = parse(replace_once(kBase, "\"box.msh\"", "\"" + mesh.string() + "\""));
  EXPECT_EQ(s.mesh.file, mesh);
}

TEST_F(ParseScene, SyntaxErrorGivesLineAndColumn) {
  const std::string message = error(replace_once(kBase, "unit = 0.01", "unit = 0.01 0.02"));
  const std::string prefix = scene_path_.string() + ":3:";
  EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
  EXPECT_TRUE(std::regex_match(message, std::regex(".*:3:[0-9]+: .+"))) << message;
  // A table header left open.
  const std::string header = error(replace_once(kBase, "[grid]", "[grid"));
  EXPECT_EQ(header.substr(0, scene_path_.string().size() + 4), scene_path_.string() + ":17:")
      << header;
}

TEST_F(ParseScene, AllProblemsReportedTogetherInLineOrder) {
  std::string text = replace_once(kBase, "substeps = 4", "substeps = 0");
  text = replace_once(text, "poisson = 0.45", "poisson = 0.7");
  text = replace_once(text, "unit = 0.01", "unit = 0.01\nunits = 2");
  text = replace_once(text, "max_force = 3.0\n", "");
  EXPECT_EQ(error(text),
            at(4, "unknown key 'mesh.units' (did you mean 'unit'?); allowed: file, unit") + "\n" +
                at(9, "key 'material.poisson' = 0.7: must be in (-1, 0.5)") + "\n" +
                at(14, "missing key 'probe.max_force' (N, the device force limit)") + "\n" +
                at(21, "key 'solver.substeps' = 0: must be in [1, 10000]"));
}

TEST_F(ParseScene, LoadSceneReadsTheFileAndResolvesAgainstIt) {
  const auto file = dir_.write("scene.toml", kBase);
  const Scene s = load_scene(file);
  EXPECT_EQ(s.text, kBase);
  EXPECT_EQ(s.mesh.file, dir_.path() / "box.msh");
  EXPECT_EQ(error_of([&] { load_scene(dir_.path() / "absent.toml"); }),
            (dir_.path() / "absent.toml").string() + ": cannot open scene file");
}

}  // namespace
}  // namespace hapstate
