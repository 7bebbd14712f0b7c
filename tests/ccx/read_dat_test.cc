// The .dat reader and the deck writer's checks, without running ccx.
#include "ccx/read_dat.h"
#include "ccx/deck.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace hapstate {
namespace {

std::filesystem::path out_dir(const std::string& name) {
  const auto dir = std::filesystem::path(HAPSTATE_BINARY_DIR) / "tests" / "ccx_out" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A single tet: node 0 fixed, node 1 grabbed in x and y (z free).
Problem one_tet() {
  Problem p;
  p.mesh.nodes.resize(3, 4);
  p.mesh.nodes << 0, 1, 0, 0,  //
      0, 0, 1, 0,              //
      0, 0, 0, 1;
  p.mesh.tets.resize(4, 1);
  p.mesh.tets << 0, 1, 2, 3;
  p.unit = 0.5;
  p.material.law = Law::kNeoHooke;
  p.material.c10 = 1;
  p.material.d1 = 0.5;
  p.constraints.role.assign(12, DofRole::kFree);
  for (int c = 0; c < 3; ++c) p.constraints.role[c] = DofRole::kFixed;
  p.constraints.role[3] = p.constraints.role[4] = DofRole::kProbe;
  p.constraints.role[5] = DofRole::kFixed;  // a fixed component of a grabbed node
  p.constraints.probe_nodes = {1};
  p.constraints.probe_components = {true, true, false};
  p.probe_rest = {1, 0, 0};
  return p;
}

TEST(CcxReadDat, ParsesTablesAndConvertsUnitsAndSigns) {
  const auto dir = out_dir("read_dat");
  std::ofstream(dir / "x.dat") << R"(
 displacements (vx,vy,vz) for set NALL and time  0.5000000E+00

         1  9.000000E+00  9.000000E+00  9.000000E+00
         2  9.000000E+00  9.000000E+00  9.000000E+00
         3  9.000000E+00  9.000000E+00  9.000000E+00
         4  9.000000E+00  9.000000E+00  9.000000E+00

 stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz) for set EALL and time  0.1000000E+01

         1   1  1.0E+00  1.0E+00  1.0E+00  1.0E+00  1.0E+00  1.0E+00

 displacements (vx,vy,vz) for set NALL and time  0.1000000E+01

         1  0.000000E+00  0.000000E+00  0.000000E+00
         2  1.000000E-01 -2.000000E-02  3.000000E-03
         3  0.000000E+00  1.000000-120  0.000000E+00
         4  0.000000E+00  0.000000E+00 -5.000000E-02

 forces (fx,fy,fz) for set PROBE and time  0.1000000E+01

         2  1.500000E+00 -2.500000E-01  7.000000E+00

 total force (fx,fy,fz) for set PROBE and time  0.1000000E+01

        1.500000E+00 -2.500000E-01  7.000000E+00
)";
  const auto blocks = read_ccx_dat(dir / "x.dat");
  ASSERT_EQ(blocks.size(), 4u);  // the stress table is skipped
  EXPECT_EQ(blocks[1].quantity, "displacements");
  EXPECT_EQ(blocks[1].set, "NALL");
  EXPECT_DOUBLE_EQ(blocks[1].time, 1.0);
  EXPECT_DOUBLE_EQ(blocks[1].values(1, 2), 1e-120);
  EXPECT_EQ(blocks[3].quantity, "total force");
  EXPECT_TRUE(blocks[3].ids.empty());

  const auto pts = ccx_path_results(one_tet(), blocks, 1);
  ASSERT_EQ(pts.size(), 1u);
  // metres -> mesh units (unit 0.5 m)
  EXPECT_DOUBLE_EQ(pts[0].displacement(0, 1), 0.2);
  EXPECT_DOUBLE_EQ(pts[0].displacement(2, 3), -0.1);
  // felt = -RF over the probe DOFs only; z of node 2 is fixed, not the user's.
  EXPECT_DOUBLE_EQ(pts[0].force_felt.x(), -1.5);
  EXPECT_DOUBLE_EQ(pts[0].force_felt.y(), 0.25);
  EXPECT_DOUBLE_EQ(pts[0].force_felt.z(), 0.0);

  EXPECT_THROW(ccx_path_results(one_tet(), blocks, 2), InputError);  // point 2 missing
}

TEST(CcxReadDat, RejectsMalformedRows) {
  const auto dir = out_dir("read_dat_bad");
  std::ofstream(dir / "x.dat") << " forces (fx,fy,fz) for set PROBE and time  0.1E+01\n\n"
                                  "         2  1.5E+00  oops  7.0E+00\n";
  EXPECT_THROW(read_ccx_dat(dir / "x.dat"), InputError);
  EXPECT_THROW(read_ccx_dat(dir / "missing.dat"), InputError);
}

TEST(CcxDeck, WritesSetsStepsAndMaterial) {
  const auto dir = out_dir("deck");
  write_ccx_deck(one_tet(), {{1.2, 0.1, 0.0}, {1.4, 0.2, 5.0}}, dir);
  std::ifstream in(dir / kCcxDeckFile);
  std::stringstream deck;
  deck << in.rdbuf();
  const std::string s = deck.str();
  EXPECT_NE(s.find("1, 0, 0, 0\n2, 0.5, 0, 0\n"), std::string::npos);  // metres, ids + 1
  EXPECT_NE(s.find("*ELEMENT, TYPE=C3D4, ELSET=EALL\n1, 1, 2, 3, 4\n"), std::string::npos);
  EXPECT_NE(s.find("*HYPERELASTIC, NEO HOOKE\n1, 0.5\n"), std::string::npos);
  EXPECT_NE(s.find("*NSET, NSET=FIXED_Z\n1, 2\n"), std::string::npos);
  // t = (p - rest) * unit; z does not follow the probe, so the 5.0 is not prescribed.
  EXPECT_NE(s.find("PROBE_X, 1, 1, 0.09999999999999998\nPROBE_Y, 2, 2, 0.05\n*NODE"),
            std::string::npos);
  EXPECT_NE(s.find("PROBE_X, 1, 1, 0.19999999999999996\nPROBE_Y, 2, 2, 0.1\n*NODE"),
            std::string::npos);
  EXPECT_EQ(s.find("PROBE_Z"), std::string::npos);
  for (std::string line; std::getline(deck, line);) EXPECT_LE(line.size(), 132u) << line;
  EXPECT_TRUE(std::filesystem::exists(dir / kCcxPathFile));
  EXPECT_TRUE(std::filesystem::exists(dir / kCcxMetaFile));
}

TEST(CcxDeck, MaterialMapping) {
  MaterialConstants c;
  c.law = Law::kStvk;
  c.mu =
      3;  // E = mu (3 lambda + 2 mu) / (lambda + mu) = 7.5, nu = lambda / (2 (lambda + mu)) = 0.25
  c.lambda = 3;
  EXPECT_EQ(ccx_material_cards(c), "*ELASTIC\n7.5, 0.25\n");
  EXPECT_TRUE(ccx_needs_nlgeom(Law::kStvk));
  EXPECT_FALSE(ccx_needs_nlgeom(Law::kLinear));
  c.law = Law::kMooney;
  c.c10 = 1;
  c.c01 = 0.25;
  c.d1 = 1.0 / 3;
  EXPECT_EQ(ccx_material_cards(c), "*HYPERELASTIC, MOONEY-RIVLIN\n1, 0.25, 0.3333333333333333\n");
  c.d1 = 1e-5 / 3;  // 22 characters in full: rounded to ccx's 20-character fields
  EXPECT_EQ(ccx_material_cards(c), "*HYPERELASTIC, MOONEY-RIVLIN\n1, 0.25, 3.33333333333333e-06\n");
  c.d1 = 0;  // ccx would silently substitute its default compressibility
  EXPECT_THROW(ccx_material_cards(c), InputError);
}

TEST(CcxDeck, RejectsBadInput) {
  const auto dir = out_dir("deck_bad");
  EXPECT_THROW(write_ccx_deck(one_tet(), {}, dir), InputError);
  Problem flipped = one_tet();
  std::swap(flipped.mesh.tets(1, 0), flipped.mesh.tets(2, 0));
  EXPECT_THROW(write_ccx_deck(flipped, {{1, 0, 0}}, dir), InputError);
  Problem roles = one_tet();
  roles.constraints.role.pop_back();
  EXPECT_THROW(write_ccx_deck(roles, {{1, 0, 0}}, dir), InputError);
  Problem stray = one_tet();
  stray.constraints.role[6] = DofRole::kProbe;  // node 2 is not a probe node
  EXPECT_THROW(write_ccx_deck(stray, {{1, 0, 0}}, dir), InputError);
}

}  // namespace
}  // namespace hapstate
