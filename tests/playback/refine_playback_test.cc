// The refine stage on the beam scene (pipelines/beam/): hapstate-refine -> hapstate-index ->
// runtime. Truths: the refine rows against the playback (exact at the refined points), the
// precise path solver of hapstate-eval (the refined file is no less accurate), and resuming.
#include "catalogue/catalogue.h"
#include "eval/evaluation.h"
#include "hapstate/playback.h"
#include "refined_points.h"
#include "state_suite.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace hapstate {
namespace {

using namespace test_util;

class RefinePlayback : public StateSuite {
 protected:
  static void SetUpTestSuite() {
    make_root("refine_playback");
    build_beam(*state_, kBeamScene, 2, *root_);
    index_all_nodes();
    fs::copy_file(*state_ / "playback.bin", *root_ / "plain.bin");
    // A tolerance far below the beam's estimates: every cell is refined.
    first_ = new StageResult(run_stage(
        HAPSTATE_REFINE_EXE,
        {"--state", state_->string(), "--threads", "2", "--tolerance", "1e-12", "-q"}, *root_));
    index_all_nodes();
  }
  static void TearDownTestSuite() {
    delete first_;
    StateSuite::TearDownTestSuite();
  }
  inline static StageResult* first_ = nullptr;
};

TEST_F(RefinePlayback, EveryCellIsRefinedOnceAndAResumedRunHasNothingToDo) {
  ASSERT_EQ(first_->exit_code, 0) << first_->err;
  // The beam's grid is 5 x 3 x 3 check-points: 4 x 2 x 2 cells, of which 12 have all 8
  // corners (max_force ends the expansion at the axial layers i = +-2), 98 points each.
  EXPECT_NE(first_->out.find("12 cells, 12 above the tolerance"), std::string::npos) << first_->out;
  Catalogue cat(*state_ / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(cat.refined_cells().size(), 12u);
  const std::vector<RefinementPoint> rows = cat.read_all_refinement_points();
  EXPECT_EQ(rows.size(), 12u * 98u);
  for (const RefinementPoint& r : rows) EXPECT_TRUE(r.reached) << r.failure_reason;
  const StageResult again = run_stage(
      HAPSTATE_REFINE_EXE, {"--state", state_->string(), "--tolerance", "1e-12", "-q"}, *root_);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("nothing to do"), std::string::npos) << again.out;
  Catalogue after(*state_ / "catalogue.sqlite", OpenMode::kReadOnly);
  EXPECT_EQ(after.num_refinement_points(), 12 * 98);
}

// The cursor passes through the refined points with the stored force, walking there from rest:
// inside a cell exactly; on a face between two refined cells, where the cursor may be in the
// neighbour, which solved the same point itself, to the solver's tolerance.
TEST_F(RefinePlayback, PlaybackPassesThroughTheRefinedPoints) {
  PlaybackFile file(*state_ / "playback.bin");
  file.verify();
  Catalogue cat(*state_ / "catalogue.sqlite", OpenMode::kReadOnly);
  HapticCursor cursor(file, Scheme::kHermite);
  double worst_inside = 0, worst_face = 0, scale = 0;
  int checked = 0;
  const std::vector<RefinementPoint> rows = cat.read_all_refinement_points();
  const std::vector<std::array<double, 3>> at = refined_point_positions(cat, file, rows);
  for (std::size_t n = 0; n < rows.size(); n += 5) {
    const RefinementPoint& r = rows[n];
    const int q[3] = {r.point / 25, r.point / 5 % 5, r.point % 5};
    const Force f = force_walked_from_rest(cursor, file, at[n]);
    const bool inside = q[0] % 4 && q[1] % 4 && q[2] % 4;
    double& worst = inside ? worst_inside : worst_face;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(f.value[k] - r.force[k]));
    scale = std::max(scale, std::hypot(r.force[0], r.force[1], r.force[2]));
    ++checked;
  }
  EXPECT_GT(checked, 200);
  EXPECT_LT(worst_inside, 1e-12 * scale);
  EXPECT_LT(worst_face, 1e-6 * scale);
}

// Against precise solves along a random path: the refined file is at least as accurate as
// the one without refinement (Hermite), and no less within the paper's bounds.
TEST_F(RefinePlayback, RefinedFileIsNoLessAccurate) {
  EvalOptions o;
  o.state = *state_;
  o.steps = 20;
  o.seed = 3;
  const EvalResult refined = run_eval(o);
  o.playback = *root_ / "plain.bin";
  const EvalResult plain = run_eval(o);
  auto worst = [](const EvalResult& r) {
    double w = 0;
    for (const EvalStep& s : r.steps) w = std::max(w, s.schemes[1].force_error);
    return w;
  };
  std::printf("[ info ] beam, seed 3, Hermite force error: refined %.3g, plain %.3g\n",
              worst(refined), worst(plain));
  EXPECT_LE(worst(refined), worst(plain) * 1.01 + 1e-6);
  EXPECT_LT(worst(refined), 0.01);
}

}  // namespace
}  // namespace hapstate
