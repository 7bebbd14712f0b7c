// Playback in contact mode on the bundled plate scene (pipelines/plate/: a plate clamped on
// its rim, a sphere on the column through its middle, below and above it). The paper's
// example: the same probe position holds the plate pushed up from below or down from above,
// and the cursor must play back the level of the side it came from. Truths: the precise path
// solver (hapstate-eval's experiment) and the catalogue's stored forces.
#include "catalogue/catalogue.h"
#include "eval/evaluation.h"
#include "hapstate/playback.h"
#include "state_suite.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace hapstate {
namespace {

using namespace test_util;

// The probe column: x = y = 2 cm; the plate spans z in [-0.1, 0.1] cm.
constexpr double kColumn = 2.0;

class PlatePlayback : public StateSuite {
 protected:
  static void SetUpTestSuite() {
    make_root("plate_playback");
    // The column through the middle of the bundled scene's 3-D workspace.
    const std::string scene =
        plate_variant(*root_, {{"box = [[1.8, 1.8, -1.0], [2.2, 2.2, 1.0]]",
                                "box = [[1.9, 1.9, -1.0], [2.1, 2.1, 1.0]]"}});
    ASSERT_EQ(import_stage(*state_, scene, *root_).exit_code, 0);
    ASSERT_EQ(grid_stage(*state_, *root_).exit_code, 0);
    ASSERT_EQ(expand_stage(*state_, 2, *root_).exit_code, 0);
    index_all_nodes();
  }
  // A straight path along the column from z0 to z1 in `steps` steps (z0 excluded).
  static fs::path column_path(const std::string& name, double z0, double z1, int steps) {
    const fs::path file = *root_ / (name + ".csv");
    std::ofstream out(file);
    out << "x,y,z\n";
    for (int s = 1; s <= steps; ++s)
      out << kColumn << ',' << kColumn << ',' << z0 + (z1 - z0) * s / steps << '\n';
    return file;
  }
  static EvalResult eval_along(const fs::path& path) {
    EvalOptions options;
    options.state = *state_;
    options.path_file = path;
    return run_eval(options);
  }
};

double max_force_error(const EvalResult& r, std::size_t scheme) {
  double e = 0;
  for (const EvalStep& s : r.steps) e = std::max(e, s.schemes[scheme].force_error);
  return e;
}

// Entering from below (the rest side) and from above (a contact path may start wherever the
// sphere is clear of the body): playback follows the precise solver within the paper's 4 %
// force error, Hermite closer than trilinear; both paths cross z = 0, where the plate holds
// two levels, and feel opposite normal forces there.
TEST_F(PlatePlayback, EntersFromBelowAndFromAboveLikeThePreciseSolver) {
  const EvalResult below = eval_along(column_path("below", -1.0, 0.1, 22));
  const EvalResult above = eval_along(column_path("above", 1.0, -0.1, 22));
  for (const EvalResult* r : {&below, &above}) {
    for (const EvalStep& s : r->steps) EXPECT_TRUE(s.solved) << s.failure;
    EXPECT_GT(r->max_exact_force, 0.3);  // N: the plate is pushed, not just touched
    EXPECT_LT(max_force_error(*r, 0), 0.04);
    EXPECT_LT(max_force_error(*r, 1), max_force_error(*r, 0));
    // After the first contact cell the deformation follows too (the contact onset lies inside
    // the first cell: docs/contact.md, playback).
    for (std::size_t k = 4; k < r->steps.size(); ++k)
      for (const SchemeResult& s : r->steps[k].schemes)
        EXPECT_LT(s.deformation_error_all, 0.14) << k;
  }
  // Step 20 is z = 0: pushed up from below the body pushes the probe down, and the reverse.
  const Eigen::Vector3d f_below = below.steps[19].exact_force,
                        f_above = above.steps[19].exact_force;
  ASSERT_NEAR(below.steps[19].probe.z(), 0.0, 1e-12);
  ASSERT_NEAR(above.steps[19].probe.z(), 0.0, 1e-12);
  EXPECT_LT(f_below.z(), -0.1);
  EXPECT_GT(f_above.z(), 0.1);
  EXPECT_GT(std::abs(f_below.z()) / f_below.norm(), 0.97);
  // The cursor plays the stored level exactly there; the precise solver took finer steps than
  // the expansion, and sticking contact depends a little on the steps (when each node was
  // caught): 0.8 % here.
  for (std::size_t scheme = 0; scheme < 2; ++scheme) {
    EXPECT_NEAR(below.steps[19].schemes[scheme].force.z(), f_below.z(),
                0.02 * std::abs(f_below.z()));
    EXPECT_NEAR(above.steps[19].schemes[scheme].force.z(), f_above.z(),
                0.02 * std::abs(f_above.z()));
  }
}

// At the two-level check-point z = 0 the cursor plays back exactly the stored level of the
// side it came from; leaving the plate gives exactly zero force and the rest shape.
TEST_F(PlatePlayback, KeepsTheLevelOfItsSideAndLeavesToRest) {
  PlaybackFile file(*state_ / "playback.bin");
  file.verify();
  ASSERT_TRUE(file.is_contact());
  Catalogue cat(*state_ / "catalogue.sqlite", OpenMode::kReadOnly);
  // The two stored forces at z = 0 (grid index k = 5 from the rest at z = -1).
  std::vector<double> stored_z;
  for (const Checkpoint& cp : cat.read_all_checkpoints())
    if (cp.ijk == std::array<int, 3>{0, 0, 5})
      for (const Configuration& c : cat.configurations_at(cp.id)) stored_z.push_back(c.force[2]);
  ASSERT_EQ(stored_z.size(), 2u);
  const double down = std::min(stored_z[0], stored_z[1]), up = std::max(stored_z[0], stored_z[1]);
  ASSERT_LT(down, 0.0);
  ASSERT_GT(up, 0.0);

  std::vector<float> u(3 * file.num_view_nodes());
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    for (const double side : {-1.0, 1.0}) {
      HapticCursor cursor(file, scheme);
      cursor.reset({kColumn, kColumn, side});
      // The sphere (radius 0.8 cm) is clear of the plate at rest (|z| <= 0.1 cm) where
      // |z| > 0.9: the force is exactly zero there, also inside the cell where it reaches the
      // plate (z between 0.8 and 1: docs/playback.md, "Contact onset").
      auto clear = [](double z) { return std::abs(z) > 0.9 + 1e-9; };
      int clear_steps = 0;
      for (int s = 0; s <= 100; ++s) {  // in to the mid-plane, 1 ms steps of 0.01 cm
        const double z = side * (1.0 - s / 100.0);
        const Force f = cursor.force({kColumn, kColumn, z});
        ASSERT_TRUE(std::isfinite(f.value[2]));
        if (clear(z)) {
          ++clear_steps;
          for (int r = 0; r < 3; ++r) EXPECT_EQ(f.value[r], 0.0) << z;
        } else if (std::abs(z) < 0.89) {
          EXPECT_GT(std::abs(f.value[2]), 0.0) << z;
        }
      }
      EXPECT_EQ(clear_steps, 10);
      const Force mid = cursor.force({kColumn, kColumn, 0.0});
      EXPECT_NEAR(mid.value[2], side < 0 ? down : up, 1e-9 * std::abs(down));
      Force out{};
      for (int s = 0; s <= 100; ++s) out = cursor.force({kColumn, kColumn, side * s / 100.0});
      for (int r = 0; r < 3; ++r) EXPECT_EQ(out.value[r], 0.0);
      hapstate::Snapshot snap;
      cursor.snapshot(&snap);
      displacements(file, snap, u);
      for (float x : u) ASSERT_EQ(x, 0.0f);
    }
  }
}

// The random path of hapstate-eval stays on a linear grid (the column) and plays back.
TEST_F(PlatePlayback, RandomPathOnTheColumn) {
  EvalOptions options;
  options.state = *state_;
  options.steps = 30;
  options.seed = 4;
  options.step_length = 0.15;
  const EvalResult r = run_eval(options);
  ASSERT_EQ(r.steps.size(), 30u);
  double zmax = -1e9;
  for (const EvalStep& s : r.steps) {
    EXPECT_TRUE(s.solved) << s.failure;
    EXPECT_DOUBLE_EQ(s.probe.x(), kColumn);
    EXPECT_DOUBLE_EQ(s.probe.y(), kColumn);
    zmax = std::max(zmax, s.probe.z());
    for (const SchemeResult& m : s.schemes) EXPECT_LT(m.force_error, 0.04) << s.probe.z();
  }
  EXPECT_GT(zmax, -0.9);  // this seed's walk reaches the plate (contact from z = -0.9)
  EXPECT_GT(r.max_exact_force, 0.0);
}

}  // namespace
}  // namespace hapstate
