// The haptic cursor on the synthetic field (synthetic.h), whose exact force and Jacobian are
// known everywhere: exactness at check-points, reproduction of linear fields, convergence
// orders of both schemes, continuity (the documented change bound) with missing corners and
// outside the grid, fast moves, return to rest, snapshots and deform.
#include "allocation_counter.h"
#include "hapstate/playback.h"
#include "synthetic.h"
#include "walk_bound.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <thread>

namespace hapstate {
namespace {

namespace fs = std::filesystem;
using test_util::Field;

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

class Cursor : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hapstate_cursor_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(playback::Content content, const std::string& name) {
    const fs::path f = dir_ / name;
    playback::write_file(std::move(content), f);
    return f;
  }
  // Walks a cursor from rest to 300 random points within 1.5 spacings of rest in small steps
  // and calls at(p) at each.
  template <typename At>
  static void visit_random_points(HapticCursor& cursor, const Field& field,
                                  const Eigen::Vector3d& h, unsigned seed, At&& at) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    Eigen::Vector3d p = field.origin;
    for (int n = 0; n < 300; ++n) {
      const Eigen::Vector3d target =
          field.origin + Eigen::Vector3d(u(rng) * h[0], u(rng) * h[1], u(rng) * h[2]);
      for (int s = 1; s < 10; ++s) cursor.force(arr(p + (target - p) * s / 10.0));
      p = target;
      at(p);
    }
  }
  // Max |f - f_exact| (absolute, N) over those points.
  double max_error(const PlaybackFile& file, Scheme scheme, const Field& field,
                   const Eigen::Vector3d& h) {
    HapticCursor cursor(file, scheme);
    double err = 0;
    visit_random_points(cursor, field, h, 7, [&](const Eigen::Vector3d& p) {
      err = std::max(err, (vec(cursor.force(arr(p)).value) - field.force(p)).norm());
    });
    return err;
  }
  // Max |u - u_exact| over the view nodes (absolute, mesh units) at those points.
  double max_displacement_error(const PlaybackFile& file, Scheme scheme, const Field& field,
                                const Eigen::Vector3d& h) {
    HapticCursor cursor(file, scheme);
    std::vector<float> d(3 * test_util::kSyntheticViewNodes);
    double err = 0;
    visit_random_points(cursor, field, h, 11, [&](const Eigen::Vector3d& p) {
      cursor.force(arr(p));
      Snapshot snap;
      cursor.snapshot(&snap);
      displacements(file, snap, d);
      for (int v = 0; v < test_util::kSyntheticViewNodes; ++v) {
        const Eigen::Vector3d exact = test_util::synthetic_displacement(field, v, p);
        err = std::max(err, (Eigen::Vector3d(d[3 * v], d[3 * v + 1], d[3 * v + 2]) - exact).norm());
      }
    });
    return err;
  }

  Field field_;
  fs::path dir_;
};

TEST_F(Cursor, ExactAtEveryCheckpoint) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "a.bin"));
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    HapticCursor cursor(file, scheme);
    std::vector<float> u(3 * test_util::kSyntheticViewNodes);
    for (int i = -2; i <= 2; ++i)
      for (int j = -2; j <= 2; ++j)
        for (int k = -2; k <= 2; ++k) {
          const Eigen::Vector3d p = field_.origin + Eigen::Vector3d(i * h[0], j * h[1], k * h[2]);
          const Eigen::Vector3d f = vec(cursor.force(arr(p)).value);
          EXPECT_LE((f - field_.force(p)).norm(), 1e-12 * (1 + field_.force(p).norm()))
              << i << j << k;
          EXPECT_EQ(cursor.anchor_checkpoint(), (std::array<std::int32_t, 3>{i, j, k}));
          Snapshot s;
          cursor.snapshot(&s);
          displacements(file, s, u);
          for (int v = 0; v < test_util::kSyntheticViewNodes; ++v)
            for (int r = 0; r < 3; ++r)
              EXPECT_NEAR(u[3 * v + r], test_util::synthetic_displacement(field_, v, p)[r], 1e-6);
        }
  }
}

Eigen::Matrix3d mat(const std::array<double, 9>& k) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) m(r, a) = k[3 * r + a];
  return m;
}

TEST_F(Cursor, StiffnessIsTheStoredOneAtEveryCheckpoint) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "k.bin"));
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    HapticCursor cursor(file, scheme);
    for (int i = -2; i <= 2; ++i)
      for (int j = -2; j <= 2; ++j)
        for (int k = -2; k <= 2; ++k) {
          const Eigen::Vector3d p = field_.origin + Eigen::Vector3d(i * h[0], j * h[1], k * h[2]);
          const Eigen::Matrix3d jac = field_.jacobian(p);
          EXPECT_LE((mat(cursor.force(arr(p)).stiffness) - jac).norm(), 1e-12 * (1 + jac.norm()))
              << i << j << k;
        }
  }
}

// Inside a cell the Hermite stiffness is the derivative of the interpolated force: central
// differences of force() (step 1e-6 of the spacing, cell interiors only) agree to 1e-6 of the
// stiffness's norm. The trilinear scheme returns the blend of the corners' stiffness, which
// stays within the field's curvature of the true Jacobian.
TEST_F(Cursor, HermiteStiffnessIsTheDerivativeOfTheInterpolatedForce) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "kd.bin"));
  HapticCursor cursor(file, Scheme::kHermite);
  HapticCursor trilinear(file, Scheme::kTrilinear);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> cell(-2.0, 2.0), inner(0.05, 0.95);
  double worst = 0, worst_tri = 0;
  for (int n = 0; n < 200; ++n) {
    Eigen::Vector3d p = field_.origin;
    for (int a = 0; a < 3; ++a) p[a] += (std::floor(cell(rng)) + inner(rng)) * h[a];
    const Force at = cursor.force(arr(p));
    Eigen::Matrix3d fd;
    for (int a = 0; a < 3; ++a) {
      const double e = 1e-6 * h[a];
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[a] = e;
      fd.col(a) =
          (vec(cursor.force(arr(p + dp)).value) - vec(cursor.force(arr(p - dp)).value)) / (2 * e);
    }
    const Eigen::Matrix3d k = mat(at.stiffness);
    worst = std::max(worst, (k - fd).norm() / k.norm());
    const Eigen::Matrix3d jac = field_.jacobian(p);
    worst_tri =
        std::max(worst_tri, (mat(trilinear.force(arr(p)).stiffness) - jac).norm() / jac.norm());
  }
  std::printf("hermite stiffness vs central differences %.3g; trilinear blend vs exact %.3g\n",
              worst, worst_tri);
  EXPECT_LE(worst, 1e-6);
  EXPECT_LE(worst_tri, 0.5);  // a blend, not the derivative: within the field's variation
}

TEST_F(Cursor, OutsideTheGridTheStiffnessIsTheExtensionsSlope) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "ko.bin"));
  HapticCursor cursor(file, Scheme::kHermite);
  const Eigen::Vector3d edge = field_.origin + Eigen::Vector3d(2 * h[0], 0.3 * h[1], 0.2 * h[2]);
  for (int s = 1; s <= 20; ++s)
    cursor.force(arr(field_.origin + (edge - field_.origin) * s / 20.0));
  const Eigen::Vector3d out = edge + Eigen::Vector3d(0.1, 0, 0);
  const Force f = cursor.force(arr(out));
  ASSERT_FALSE(f.inside_grid);
  const Force g = cursor.force(arr(out + Eigen::Vector3d(1e-3, 0, 0)));
  EXPECT_LE((mat(f.stiffness).col(0) - (vec(g.value) - vec(f.value)) / 1e-3).norm(),
            1e-9 * mat(f.stiffness).norm());
}

TEST_F(Cursor, BothSchemesReproduceALinearField) {
  Field linear = field_;
  linear.amplitude = 0;
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(linear, h), "linear.bin"));
  EXPECT_LE(max_error(file, Scheme::kTrilinear, linear, h), 1e-12);
  EXPECT_LE(max_error(file, Scheme::kHermite, linear, h), 1e-12);
  // The displacements too (float32 storage: 1e-6 of their size).
  EXPECT_LE(max_displacement_error(file, Scheme::kTrilinear, linear, h), 1e-6);
  EXPECT_LE(max_displacement_error(file, Scheme::kHermite, linear, h), 1e-6);
}

TEST_F(Cursor, HermiteDisplacementsConvergeFasterThanTrilinear) {
  // As the force: halving the spacing divides the trilinear error by about 4 and the Hermite
  // error (corner slopes as derivatives, cross derivatives estimated) by 8 or more.
  double tri[2], her[2];
  for (int level = 0; level < 2; ++level) {
    const Eigen::Vector3d h = Eigen::Vector3d(0.5, 0.4, 0.6) / (level ? 2.0 : 1.0);
    PlaybackFile file(
        write(test_util::synthetic_content(field_, h), "dconv" + std::to_string(level) + ".bin"));
    ASSERT_TRUE(file.has_displacement_slopes());
    tri[level] = max_displacement_error(file, Scheme::kTrilinear, field_, h);
    her[level] = max_displacement_error(file, Scheme::kHermite, field_, h);
  }
  std::printf("max displacement error trilinear %.3g -> %.3g, hermite %.3g -> %.3g\n", tri[0],
              tri[1], her[0], her[1]);
  EXPECT_GT(tri[0] / tri[1], 3.0);
  EXPECT_GT(her[0] / her[1], 6.0);
  EXPECT_LT(her[0], tri[0] / 3);
  EXPECT_LT(her[1], tri[1] / 6);
}

TEST_F(Cursor, WithoutSlopesHermiteDeformationIsTrilinear) {
  // A file indexed from a state without displacement slopes: Hermite deform() blends like
  // trilinear (and says so through has_displacement_slopes()).
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content c = test_util::synthetic_content(field_, h);
  c.displacement_slopes = nullptr;
  PlaybackFile file(write(std::move(c), "noslopes.bin"));
  EXPECT_FALSE(file.has_displacement_slopes());
  EXPECT_TRUE(file.displacement_slopes(0, 0).empty());
  EXPECT_NEAR(max_displacement_error(file, Scheme::kHermite, field_, h),
              max_displacement_error(file, Scheme::kTrilinear, field_, h), 1e-9);
}

TEST_F(Cursor, HermiteConvergesFasterThanTrilinear) {
  // Halving the spacing: trilinear error / 4 (second order), Hermite / 8 or better (third order
  // with estimated cross derivatives, fourth along the axes).
  double tri[2], her[2];
  for (int level = 0; level < 2; ++level) {
    const Eigen::Vector3d h = Eigen::Vector3d(0.5, 0.4, 0.6) / (level ? 2.0 : 1.0);
    PlaybackFile file(
        write(test_util::synthetic_content(field_, h), "conv" + std::to_string(level) + ".bin"));
    tri[level] = max_error(file, Scheme::kTrilinear, field_, h);
    her[level] = max_error(file, Scheme::kHermite, field_, h);
  }
  RecordProperty("trilinear", std::to_string(tri[0]) + " -> " + std::to_string(tri[1]));
  RecordProperty("hermite", std::to_string(her[0]) + " -> " + std::to_string(her[1]));
  std::printf("max error trilinear %.3g -> %.3g, hermite %.3g -> %.3g\n", tri[0], tri[1], her[0],
              her[1]);
  EXPECT_GT(tri[0] / tri[1], 3.0);
  EXPECT_GT(her[0] / her[1], 6.0);
  EXPECT_LT(her[0], tri[0] / 3);
  EXPECT_LT(her[1], tri[1] / 6);
}

using test_util::check_bound_along_random_walk;

TEST_F(Cursor, ContinuousWithMissingCornersAndOutsideTheGrid) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content c = test_util::synthetic_content(field_, h);
  // The +x half was never expanded, some transitions failed, and check-points with i = 2
  // were never reached at all.
  for (int g = 0; g < 125; ++g) {
    const int i = g / 25 - 2;
    for (int d = 0; d < 26; ++d) {
      std::int32_t& t = c.transitions[26 * g + d];
      if (i >= 1) t = playback::kUndecided;
      if ((g + d) % 7 == 0) t = playback::kFailed;
      if (t >= 0 && t / 25 - 2 == 2) t = playback::kUndecided;
    }
  }
  PlaybackFile file(write(std::move(c), "holes.bin"));
  file.verify();
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite})
    RecordProperty(scheme == Scheme::kHermite ? "hermite_worst" : "trilinear_worst",
                   std::to_string(check_bound_along_random_walk(file, scheme, 10000)));
  // Near the rest state nothing is missing: still exact at a check-point.
  HapticCursor cursor(file, Scheme::kHermite);
  const Eigen::Vector3d p = field_.origin + Eigen::Vector3d(-h[0], 0, h[2]);
  EXPECT_LE((vec(cursor.force(arr(p)).value) - field_.force(p)).norm(), 1e-12);
  // In the unreached layer the corners are extended, and marked so.
  cursor.force(arr(field_.origin + Eigen::Vector3d(1.9 * h[0], 0, 0)));
  int extended = 0;
  for (int k = 0; k < 8; ++k) extended += cursor.corner_source(k) == CornerSource::kExtended;
  EXPECT_GE(extended, 4);
  // At the unreached check-point (2, 0, 0) the Hermite displacements are those of (1, 0, 0)
  // extended by its slopes (first-order Taylor), the trilinear ones those of (1, 0, 0).
  const Eigen::Vector3d p1 = field_.origin + Eigen::Vector3d(h[0], 0, 0);
  const Eigen::Vector3d p2 = field_.origin + Eigen::Vector3d(2 * h[0], 0, 0);
  std::vector<float> d(3 * test_util::kSyntheticViewNodes);
  for (Scheme scheme : {Scheme::kHermite, Scheme::kTrilinear}) {
    cursor.set_scheme(scheme);
    cursor.force(arr(p2));
    Snapshot snap;
    cursor.snapshot(&snap);
    displacements(file, snap, d);
    for (int v = 0; v < test_util::kSyntheticViewNodes; ++v) {
      Eigen::Vector3d want = test_util::synthetic_displacement(field_, v, p1);
      if (scheme == Scheme::kHermite)
        want += test_util::synthetic_displacement_slope(field_, v, p1) * (p2 - p1);
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(d[3 * v + r], want[r], 1e-5) << v << r;
    }
  }
}

TEST_F(Cursor, PlanarWorkspaceWithOneCheckpointAlongAnAxis) {
  // A workspace flat in z: in the plane the cursor interpolates in x and y; off the plane the
  // force is extended with the stiffness (as outside any grid).
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h, true), "flat.bin"));
  file.verify();
  EXPECT_EQ(file.grid_dims()[2], 1);
  for (Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    HapticCursor cursor(file, scheme);
    const Eigen::Vector3d p = field_.origin + Eigen::Vector3d(1.0 * h[0], -2.0 * h[1], 0);
    for (int s = 1; s <= 10; ++s) cursor.force(arr(field_.origin + (p - field_.origin) * s / 10.0));
    EXPECT_LE((vec(cursor.force(arr(p)).value) - field_.force(p)).norm(), 1e-12);
    const Force off = cursor.force(arr(p + Eigen::Vector3d(0, 0, 0.01)));
    EXPECT_FALSE(off.inside_grid);
    EXPECT_LE((vec(off.value) - field_.force(p) - field_.jacobian(p) * Eigen::Vector3d(0, 0, 0.01))
                  .norm(),
              1e-12);
    // Between check-points in the plane: close to the field (second order in the spacing).
    const Eigen::Vector3d mid = field_.origin + Eigen::Vector3d(0.5 * h[0], -1.5 * h[1], 0);
    EXPECT_LE((vec(cursor.force(arr(mid)).value) - field_.force(mid)).norm(), 0.05);
  }
  RecordProperty("worst",
                 std::to_string(check_bound_along_random_walk(file, Scheme::kHermite, 10000)));
}

TEST_F(Cursor, OutsideTheGridTheForceIsExtendedContinuously) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "b.bin"));
  HapticCursor cursor(file, Scheme::kTrilinear);
  const Eigen::Vector3d edge = field_.origin + Eigen::Vector3d(2 * h[0], 0, 0);
  const Eigen::Vector3d f_edge = vec(cursor.force(arr(edge)).value);
  const Force out = cursor.force(arr(edge + Eigen::Vector3d(0.01, 0, 0)));
  EXPECT_FALSE(out.inside_grid);
  const Eigen::Vector3d expected = f_edge + field_.jacobian(edge) * Eigen::Vector3d(0.01, 0, 0);
  EXPECT_LE((vec(out.value) - expected).norm(), 1e-12);
  check_bound_along_random_walk(file, Scheme::kHermite, 10000);
}

TEST_F(Cursor, FastMoveWalksTheCellsAndReturnsToRest) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "c.bin"));
  HapticCursor slow(file, Scheme::kHermite), fast(file, Scheme::kHermite);
  const Eigen::Vector3d far = field_.origin + Eigen::Vector3d(1.7 * h[0], -1.3 * h[1], 1.9 * h[2]);
  for (int s = 1; s <= 100; ++s) slow.force(arr(field_.origin + (far - field_.origin) * s / 100.0));
  const Force f = fast.force(arr(far));
  EXPECT_EQ(fast.cells_walked(), 4u);  // cell (0, 0, 0) -> (1, -2, 1): one face at a time
  EXPECT_LE((vec(f.value) - vec(slow.force(arr(far)).value)).norm(), 1e-12);
  EXPECT_EQ(vec(fast.force(arr(field_.origin)).value).norm(), 0.0);
  EXPECT_EQ(vec(slow.force(arr(field_.origin)).value).norm(), 0.0);
}

// With the force (and stiffness) recorded half-way through the moves (synthetic.h,
// add_midpoint_forces), the force of either scheme passes through it at every edge midpoint,
// face centre and cell centre and stays exact at the check-points with the stored stiffness
// there (Hermite with the midpoint stiffness: at the midpoints too); the Hermite stiffness is the
// derivative of the force; the error between check-points falls, and the change bound holds.
TEST_F(Cursor, ForcePassesThroughTheMidpointForces) {
  const Field field;
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content content = test_util::synthetic_content(field, h);
  const fs::path plain_file = write(content, "plain.bin");
  test_util::add_midpoint_forces(&content, field, false);
  const fs::path bubbles_file = write(content, "bubbles.bin");
  test_util::add_midpoint_forces(&content, field, true);
  const fs::path lattice_file = write(content, "lattice.bin");
  PlaybackFile plain(plain_file), bubbles(bubbles_file), lattice(lattice_file);
  bubbles.verify();
  lattice.verify();
  for (const PlaybackFile* file : {&bubbles, &lattice})
    for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
      const bool half_cells = file == &lattice && scheme == Scheme::kHermite;
      SCOPED_TRACE(std::string(scheme == Scheme::kHermite ? "hermite" : "trilinear") +
                   (file == &lattice ? ", midpoint stiffness" : ", midpoint forces"));
      HapticCursor cursor(*file, scheme);
      for (int i = -1; i <= 0; ++i)
        for (int j = -1; j <= 0; ++j)
          for (int k = -1; k <= 0; ++k)
            for (int di = 0; di <= 2; ++di)
              for (int dj = 0; dj <= 2; ++dj)
                for (int dk = 0; dk <= 2; ++dk) {
                  const Eigen::Vector3d p =
                      field.origin + Eigen::Vector3d((i + 0.5 * di) * h[0], (j + 0.5 * dj) * h[1],
                                                     (k + 0.5 * dk) * h[2]);
                  const Force f = cursor.force(arr(p));
                  EXPECT_LT((vec(f.value) - field.force(p)).norm(), 1e-12)
                      << i << j << k << " + " << di << dj << dk << " halves";
                  if (half_cells || (di % 2 == 0 && dj % 2 == 0 && dk % 2 == 0)) {
                    const Eigen::Matrix3d jac = field.jacobian(p);
                    for (int r = 0; r < 3; ++r)
                      for (int a = 0; a < 3; ++a)
                        EXPECT_NEAR(f.stiffness[3 * r + a], jac(r, a), 1e-12);
                  }
                }
    }
  // The stiffness is the derivative of the force inside a cell.
  for (const PlaybackFile* file : {&bubbles, &lattice}) {
    HapticCursor cursor(*file, Scheme::kHermite);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    for (int n = 0; n < 20; ++n) {
      const Eigen::Vector3d p =
          field.origin + Eigen::Vector3d((u(rng) - 1) * h[0], u(rng) * h[1], (u(rng) - 1) * h[2]);
      const Force f = cursor.force(arr(p));
      const double d = 1e-6;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e[a] = d * h[a];
        const Eigen::Vector3d fp = vec(cursor.force(arr(p + e)).value);
        const Eigen::Vector3d fm = vec(cursor.force(arr(p - e)).value);
        for (int r = 0; r < 3; ++r)
          EXPECT_NEAR(f.stiffness[3 * r + a], (fp[r] - fm[r]) / (2 * e[a]), 1e-6);
      }
    }
  }
  const double without = max_error(plain, Scheme::kHermite, field, h);
  const double with_forces = max_error(bubbles, Scheme::kHermite, field, h);
  const double with_stiffness = max_error(lattice, Scheme::kHermite, field, h);
  const double without_tri = max_error(plain, Scheme::kTrilinear, field, h);
  const double with_tri = max_error(lattice, Scheme::kTrilinear, field, h);
  std::printf(
      "[ info ] force error between check-points without / with the midpoint forces / and "
      "stiffness: Hermite %.3g / %.3g / %.3g N, trilinear %.3g / %.3g N\n",
      without, with_forces, with_stiffness, without_tri, with_tri);
  EXPECT_LT(with_forces, 0.6 * without);  // measured 0.50
  // Hermite on half-spacing cells (second-order cross derivatives): the error of a smooth field
  // falls about 38x.
  EXPECT_LT(with_stiffness, 0.05 * without);  // measured 0.026
  // Trilinear on the half-spacing lattice: the error of a smooth field falls about 4x.
  EXPECT_LT(with_tri, 0.35 * without_tri);
  for (const PlaybackFile* file : {&bubbles, &lattice})
    for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite})
      EXPECT_LE(test_util::check_bound_along_random_walk(*file, scheme, 10000), 1.0);
}

// With the midpoint stiffness, each half-spacing cell is a cubic Hermite cell whose cross
// derivatives come from parabolas through the gradients of the cell's 3 x 3 x 3 lattice (second
// order). So: more accurate than the grid of half the spacing, whose cells estimate them from
// their own two corners (first order); the error falls about 16x per halving of the spacing (the
// cubic's fourth order); and the force stays continuous across every face, of the cells and of
// the half cells, also where midpoints are missing.
TEST_F(Cursor, MidpointStiffnessIsMoreAccurateThanTheHalfSpacingGrid) {
  const Field field;
  auto lattice_content = [&](const Eigen::Vector3d& h) {
    playback::Content content = test_util::synthetic_content(field, h);
    test_util::add_midpoint_forces(&content, field, true);
    return content;
  };
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile lattice(write(lattice_content(h), "lattice.bin"));
  PlaybackFile finer(write(lattice_content(0.5 * h), "finer.bin"));
  PlaybackFile fine(write(test_util::synthetic_content(field, 0.5 * h), "fine.bin"));
  // Over the region the half-spacing files span (+-h), largest force error.
  auto error = [&](const PlaybackFile& file, double reach) {
    HapticCursor cursor(file, Scheme::kHermite);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-reach, reach);
    double worst = 0;
    for (int n = 0; n < 500; ++n) {
      const Eigen::Vector3d p =
          field.origin + Eigen::Vector3d(u(rng) * h[0], u(rng) * h[1], u(rng) * h[2]);
      const Force f = cursor.force(arr(p));
      EXPECT_TRUE(f.inside_grid);
      worst = std::max(worst, (vec(f.value) - field.force(p)).norm());
    }
    return worst;
  };
  const double on_lattice = error(lattice, 0.999), on_finer = error(finer, 0.999),
               on_fine = error(fine, 0.999);
  std::printf(
      "[ info ] Hermite force error: midpoint lattice %.3g N, the same at half the spacing %.3g N "
      "(%.1fx less), the grid of half the spacing %.3g N\n",
      on_lattice, on_finer, on_lattice / on_finer, on_fine);
  EXPECT_LT(on_lattice, 0.5 * on_fine);    // measured 0.33
  EXPECT_GT(on_lattice / on_finer, 12.0);  // measured 17.5
  // Continuity: with some midpoints missing (the corners' cubic stands in there), the force on
  // either side of every face, of the cells and of the half cells, agrees.
  playback::Content holes = lattice_content(h);
  for (std::size_t k = 0; k < holes.midpoint_force.size() / 3; k += 3)
    for (int r = 0; r < 3; ++r) holes.midpoint_force[3 * k + r] = std::nan("");
  PlaybackFile holed(write(std::move(holes), "holes.bin"));
  HapticCursor cursor(holed, Scheme::kHermite);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  std::uniform_int_distribution<int> face(-3, 3);
  const double eps = 1e-9;
  double jump = 0;
  for (int n = 0; n < 600; ++n) {
    const int axis = n % 3;
    Eigen::Vector3d p(u(rng) * h[0], u(rng) * h[1], u(rng) * h[2]);
    p[axis] = 0.5 * face(rng) * h[axis];  // a face of a cell (even) or of a half cell (odd)
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[axis] = eps;
    const Eigen::Vector3d below = vec(cursor.force(arr(field.origin + p - e)).value);
    const Eigen::Vector3d above = vec(cursor.force(arr(field.origin + p + e)).value);
    jump = std::max(jump, (above - below).norm());
  }
  EXPECT_LT(jump, 1e-7);  // a slope of order 1 N per unit times 2e-9
}

// Refined cells (docs/playback.md, "Refined cells"): two neighbouring cells with their
// quarter-spacing points. The force passes through every point a refined cell uses, is about an
// order of magnitude closer to the field in those cells than without them (the quarter cells'
// h^4), stays continuous across every face (between the two refined cells, and where a refined
// cell borders one that is not: there the half cells' interpolant is reproduced), and its
// stiffness is the derivative of the force inside. The trilinear scheme interpolates the same
// points trilinearly on the quarter cells: exact at them, closer to the field (h^2) and
// continuous too.
TEST_F(Cursor, RefinedCellsPassThroughTheirPointsAndStayContinuous) {
  const Field field;
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content plain = test_util::synthetic_content(field, h);
  test_util::add_midpoint_forces(&plain, field, true);
  playback::Content refined = plain;
  test_util::add_refined_cells(&refined, field, {{0, 0, 0}, {-1, 0, 0}});
  ASSERT_EQ(refined.refined_points.size(), 2u * 12 * playback::kRefinedPoints);
  // Cell (0, 0, 0) borders the refined cell (-1, 0, 0) on its face x = 0 only.
  const std::int32_t bits =
      refined.refined_cells[playback::kRefinedCellInts * refined.checkpoints[2 * 62] + 1];
  EXPECT_EQ(bits & (1 << playback::refined_face_bit(0, 0)), 0);
  EXPECT_NE(bits & (1 << playback::refined_face_bit(0, 1)), 0);
  PlaybackFile with(write(std::move(refined), "refined.bin"));
  with.verify();
  PlaybackFile without(write(std::move(plain), "plain.bin"));
  HapticCursor cursor(with, Scheme::kHermite), trilinear(with, Scheme::kTrilinear);
  auto at = [&](double x, double y, double z) {
    return Eigen::Vector3d(field.origin[0] + x * h[0], field.origin[1] + y * h[1],
                           field.origin[2] + z * h[2]);
  };
  // Exact at the points inside the refined pair (its outer faces take the half cells').
  double worst_point = 0, worst_trilinear_point = 0, worst_trilinear_k = 0;
  for (int i = 1; i < 8; ++i)
    for (int j = 1; j < 4; ++j)
      for (int k = 1; k < 4; ++k) {
        const Eigen::Vector3d p = at(-1.0 + 0.25 * i, 0.25 * j, 0.25 * k);
        worst_point =
            std::max(worst_point, (vec(cursor.force(arr(p)).value) - field.force(p)).norm());
        const Force t = trilinear.force(arr(p));
        worst_trilinear_point =
            std::max(worst_trilinear_point, (vec(t.value) - field.force(p)).norm());
        // The stiffness: the solved one at a refined point (at the half-spacing lattice's, the
        // corners' blended, as without refinement).
        if (i % 2 || j % 2 || k % 2)
          worst_trilinear_k =
              std::max(worst_trilinear_k, (mat(t.stiffness) - field.jacobian(p)).norm());
      }
  EXPECT_LT(worst_point, 1e-12);
  EXPECT_LT(worst_trilinear_point, 1e-12);
  EXPECT_LT(worst_trilinear_k, 1e-12);
  // Accuracy inside the pair, with and without the refinement (away from the faces shared with
  // cells that are not refined, where the half cells' interpolant is kept).
  auto error = [&](const PlaybackFile& file, Scheme scheme) {
    HapticCursor c(file, scheme);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.25, 0.75);
    double worst = 0;
    for (int n = 0; n < 400; ++n) {
      const Eigen::Vector3d p = at(3.0 * u(rng) - 1.5, u(rng), u(rng));
      worst = std::max(worst, (vec(c.force(arr(p)).value) - field.force(p)).norm());
    }
    return worst;
  };
  const double refined_error = error(with, Scheme::kHermite),
               plain_error = error(without, Scheme::kHermite);
  std::printf("[ info ] Hermite force error in the refined cells %.3g N, without them %.3g N\n",
              refined_error, plain_error);
  EXPECT_LT(refined_error, 0.2 * plain_error);
  const double refined_trilinear = error(with, Scheme::kTrilinear),
               plain_trilinear = error(without, Scheme::kTrilinear);
  std::printf("[ info ] trilinear force error in the refined cells %.3g N, without them %.3g N\n",
              refined_trilinear, plain_trilinear);
  EXPECT_LT(refined_trilinear, 0.4 * plain_trilinear);
  // Continuity across faces of cells, half cells and quarter cells around the pair, and around
  // an L of three refined cells whose fourth cell on their shared edge is not refined (the edge
  // is constrained, the faces between the three are not), where two points of a shared face
  // failed in one of the two cells that solved them (the index gives both the other's).
  auto max_jump = [&](HapticCursor& c) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> u(-1.999, 1.999);
    std::uniform_int_distribution<int> face(-8, 8);
    const double eps = 1e-9;
    double jump = 0;
    for (int n = 0; n < 1500; ++n) {
      const int axis = n % 3;
      Eigen::Vector3d q(u(rng), u(rng), u(rng));
      q[axis] = 0.25 * face(rng);
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = eps;
      const Eigen::Vector3d p = at(q[0], q[1], q[2]);
      const Eigen::Vector3d below = vec(c.force(arr(p - e)).value);
      const Eigen::Vector3d above = vec(c.force(arr(p + e)).value);
      jump = std::max(jump, (above - below).norm());
    }
    return jump;
  };
  EXPECT_LT(max_jump(cursor), 1e-7);
  EXPECT_LT(max_jump(trilinear), 1e-7);
  // Its refined points from a perturbed field, so that a refined point used where the half
  // cells' interpolant belongs (a constraint missed) shows as a jump of about 1e-3 N.
  playback::Content l_shape = test_util::synthetic_content(field, h);
  test_util::add_midpoint_forces(&l_shape, field, true);
  test_util::add_refined_cells(&l_shape, test_util::Perturbed<Field>{field},
                               {{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}},
                               {{{0, 0, 0}, 0 * 25 + 5 * 1 + 1}, {{-1, 0, 0}, 4 * 25 + 5 * 3 + 2}});
  PlaybackFile l_file(write(std::move(l_shape), "l_shape.bin"));
  HapticCursor l_cursor(l_file, Scheme::kHermite);
  const double l_jump = max_jump(l_cursor);
  std::printf("[ info ] largest jump across a face, L of refined cells: %.3g N\n", l_jump);
  EXPECT_LT(l_jump, 1e-7);  // without the diagonal edge's constraint: 4.3e-7
  HapticCursor l_trilinear(l_file, Scheme::kTrilinear);
  const double l_trilinear_jump = max_jump(l_trilinear);
  std::printf("[ info ] largest jump across a face, L of refined cells, trilinear: %.3g N\n",
              l_trilinear_jump);
  EXPECT_LT(l_trilinear_jump, 1e-7);
  // The L again with each cell's solves 1e-6 N apart, as two solves of one point are within the
  // solver's tolerance: the two arms solved the points of the edge they share with the corner
  // cell (0, 0, 0), and the cell between the arms is not refined. The index gives each point one
  // value (the lowest cell's; it once copied the arms' values into the corner cell in turn
  // without end) and the force stays continuous.
  playback::Content apart = test_util::synthetic_content(field, h);
  test_util::add_midpoint_forces(&apart, field, true);
  test_util::add_refined_cells(&apart, test_util::Perturbed<Field>{field},
                               {{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}}, {}, {}, {}, 1e-6);
  const std::int32_t corner_cell = apart.checkpoints[2 * 62];  // the grid point (0, 0, 0)
  const double* corner_points =
      &apart.refined_points[12 * playback::kRefinedPoints *
                            apart.refined_cells[playback::kRefinedCellInts * corner_cell]];
  for (int l = 1; l < 5; l += 2) {  // the edge x = y = 0: the arm (-1, 0, 0)'s value, 1e-6 up
    const Eigen::Vector3d p = at(0, 0, 0.25 * l);
    EXPECT_NEAR(corner_points[12 * l], test_util::Perturbed<Field>{field}.force(p)[0] + 1e-6, 1e-12)
        << l;
  }
  PlaybackFile apart_file(write(std::move(apart), "l_apart.bin"));
  HapticCursor apart_cursor(apart_file, Scheme::kHermite);
  const double apart_jump = max_jump(apart_cursor);
  std::printf("[ info ] largest jump across a face, L of cells whose solves differ: %.3g N\n",
              apart_jump);
  EXPECT_LT(apart_jump, 1e-7);
  // The stiffness inside a refined cell: central differences of the force.
  double worst_k = 0, scale = 0;
  for (int n = 0; n < 20; ++n) {
    const Eigen::Vector3d p = at(0.05 + 0.045 * n, 0.3 + 0.02 * n, 0.9 - 0.04 * n);
    const Eigen::Matrix3d k = mat(cursor.force(arr(p)).stiffness);
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[a] = 1e-6;
      const Eigen::Vector3d fd =
          (vec(cursor.force(arr(p + d)).value) - vec(cursor.force(arr(p - d)).value)) / 2e-6;
      worst_k = std::max(worst_k, (fd - k.col(a)).norm());
      scale = std::max(scale, k.col(a).norm());
    }
  }
  EXPECT_LT(worst_k, 1e-6 * scale);
}

// With the midpoint displacements and slopes too, deform() interpolates each half-spacing cell
// as the force: the same displacements as the grid of half the spacing, exact at the stored
// midpoints, and a file without them keeps the corner cubic (a larger error). A snapshot whose
// midpoint codes name nothing stored (damaged, or from the C interface) gives that cubic too.
TEST_F(Cursor, MidpointDisplacementsEqualTheHalfSpacingGrid) {
  const Field field;
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content content = test_util::synthetic_content(field, h);
  test_util::add_midpoint_forces(&content, field, true);
  PlaybackFile corners_only(write(content, "corners_only.bin"));
  test_util::add_midpoint_displacements(&content, field);
  PlaybackFile lattice(write(content, "lattice_u.bin"));
  PlaybackFile fine(write(test_util::synthetic_content(field, 0.5 * h), "fine_u.bin"));
  HapticCursor coarse_cursor(lattice, Scheme::kHermite), fine_cursor(fine, Scheme::kHermite),
      plain_cursor(corners_only, Scheme::kHermite);
  std::vector<float> a(3 * test_util::kSyntheticViewNodes), b(a.size()), c(a.size());
  auto displacements_at = [&](HapticCursor& cursor, const PlaybackFile& file,
                              const Eigen::Vector3d& p, std::vector<float>* out) {
    cursor.force(arr(p));
    Snapshot snap;
    cursor.snapshot(&snap);
    displacements(file, snap, *out);
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.999, 0.999);  // the fine grid spans +-h
  double to_fine = 0, lattice_error = 0, plain_error = 0, scale = 0;
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d p =
        field.origin + Eigen::Vector3d(u(rng) * h[0], u(rng) * h[1], u(rng) * h[2]);
    displacements_at(coarse_cursor, lattice, p, &a);
    displacements_at(fine_cursor, fine, p, &b);
    displacements_at(plain_cursor, corners_only, p, &c);
    for (int v = 0; v < test_util::kSyntheticViewNodes; ++v) {
      const Eigen::Vector3d exact = test_util::synthetic_displacement(field, v, p);
      const Eigen::Vector3d x(a[3 * v], a[3 * v + 1], a[3 * v + 2]);
      to_fine =
          std::max(to_fine, (x - Eigen::Vector3d(b[3 * v], b[3 * v + 1], b[3 * v + 2])).norm());
      lattice_error = std::max(lattice_error, (x - exact).norm());
      plain_error = std::max(
          plain_error, (Eigen::Vector3d(c[3 * v], c[3 * v + 1], c[3 * v + 2]) - exact).norm());
      scale = std::max(scale, exact.norm());
    }
  }
  std::printf(
      "displacement error: corners only %.3g, half-spacing cells %.3g (to the fine grid "
      "%.3g, displacements up to %.3g)\n",
      plain_error, lattice_error, to_fine, scale);
  EXPECT_LE(to_fine, 1e-6 * scale);  // float32 storage
  EXPECT_LT(lattice_error, plain_error / 6);
  {
    const Eigen::Vector3d p = field.origin + Eigen::Vector3d(0.3 * h[0], 0.6 * h[1], 0.2 * h[2]);
    coarse_cursor.force(arr(p));
    Snapshot snap;
    coarse_cursor.snapshot(&snap);
    ASSERT_GT(*std::max_element(snap.midpoint.begin(), snap.midpoint.end()), 0);
    const std::int32_t bad[] = {-5, 0x7fffffff, 7 * 125 + 1};
    for (int k = 0; k < 27; ++k) snap.midpoint[k] = bad[k % 3];
    displacements(lattice, snap, a);
    plain_cursor.force(arr(p));
    Snapshot plain_snap;
    plain_cursor.snapshot(&plain_snap);
    displacements(corners_only, plain_snap, c);
    for (std::size_t r = 0; r < a.size(); ++r) EXPECT_EQ(a[r], c[r]) << r;
  }
  // Exact at a stored midpoint: the centre of the cell above the rest point.
  const Eigen::Vector3d centre = field.origin + 0.5 * h;
  displacements_at(coarse_cursor, lattice, centre, &a);
  for (int v = 0; v < test_util::kSyntheticViewNodes; ++v) {
    const Eigen::Vector3d exact = test_util::synthetic_displacement(field, v, centre);
    EXPECT_LE((Eigen::Vector3d(a[3 * v], a[3 * v + 1], a[3 * v + 2]) - exact).norm(), 1e-6 * scale);
  }
}

// A recorded value is used only where the source's move leads to the configuration the cell
// shows at the other end: with the +x move of the rest configuration marked failed, the force at
// that edge's midpoint is the plain Hermite one, and the rest of the cell still uses its recorded
// values.
TEST_F(Cursor, MidpointForceOfAMoveThatDoesNotReachTheCornerIsNotUsed) {
  const Field field;
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content content = test_util::synthetic_content(field, h);
  const int rest = content.meta.rest_configuration;
  content.transitions[26 * rest + test_util::direction_of(1, 0, 0)] = playback::kFailed;
  const fs::path plain_file = write(content, "plain.bin");
  PlaybackFile plain(plain_file);
  for (const bool stiffness : {false, true}) {
    SCOPED_TRACE(stiffness ? "midpoint stiffness" : "midpoint forces");
    test_util::add_midpoint_forces(&content, field, stiffness);
    PlaybackFile file(write(content, "midpoints.bin"));
    HapticCursor with(file, Scheme::kHermite), without(plain, Scheme::kHermite);
    const Eigen::Vector3d edge = field.origin + Eigen::Vector3d(0.5 * h[0], 0, 0);
    const Force a = with.force(arr(edge)), b = without.force(arr(edge));
    EXPECT_EQ(vec(a.value), vec(b.value));
    for (int r = 0; r < 9 && stiffness; ++r) EXPECT_NEAR(a.stiffness[r], b.stiffness[r], 1e-12);
    const Eigen::Vector3d centre = field.origin + 0.5 * h;
    EXPECT_LT((vec(with.force(arr(centre)).value) - field.force(centre)).norm(), 1e-12);
  }
  // The displacements likewise: at that edge's midpoint those of the corners' cubic (the plain
  // file's), at the cell centre the stored ones.
  test_util::add_midpoint_displacements(&content, field);
  PlaybackFile file(write(content, "midpoints_u.bin"));
  HapticCursor with(file, Scheme::kHermite), without(plain, Scheme::kHermite);
  std::vector<float> a(3 * test_util::kSyntheticViewNodes), b(a.size());
  Snapshot snap;
  const Eigen::Vector3d edge = field.origin + Eigen::Vector3d(0.5 * h[0], 0, 0);
  with.force(arr(edge));
  with.snapshot(&snap);
  displacements(file, snap, a);
  without.force(arr(edge));
  without.snapshot(&snap);
  displacements(plain, snap, b);
  for (std::size_t r = 0; r < a.size(); ++r) EXPECT_NEAR(a[r], b[r], 1e-6) << r;
  const Eigen::Vector3d centre = field.origin + 0.5 * h;
  with.force(arr(centre));
  with.snapshot(&snap);
  displacements(file, snap, a);
  for (int v = 0; v < test_util::kSyntheticViewNodes; ++v)
    EXPECT_LE((Eigen::Vector3d(a[3 * v], a[3 * v + 1], a[3 * v + 2]) -
               test_util::synthetic_displacement(field, v, centre))
                  .norm(),
              1e-6);
}

TEST_F(Cursor, ForceAndSnapshotDoNotAllocate) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  playback::Content c = test_util::synthetic_content(field_, h);
  for (int d = 0; d < 26 * 125; d += 5)
    c.transitions[d] = playback::kFailed;             // extended corners too
  test_util::add_midpoint_forces(&c, field_);         // the half-cell fit at each cell entry too
  test_util::add_midpoint_displacements(&c, field_);  // and the half-cell deform
  PlaybackFile file(write(std::move(c), "alloc.bin"));
  HapticCursor cursor(file, Scheme::kHermite);
  std::vector<float> pos(3 * test_util::kSyntheticViewNodes);
  Snapshot s;
  int bad_numbers = 0;
  g_allocations = 0;
  g_counting = true;
  for (int n = 0; n < 20000; ++n) {
    const double t = 1e-3 * n;
    const Force f = cursor.force(
        {1.0 + 1.2 * std::sin(t), 2.0 + 0.9 * std::cos(1.3 * t), 3.0 + 1.5 * std::sin(0.7 * t)});
    if (!std::isfinite(f.stiffness[4])) ++bad_numbers;
    if (n % 16 == 0) {
      cursor.snapshot(&s);
      deform(file, s, pos);
    }
  }
  cursor.set_scheme(Scheme::kTrilinear);
  for (int n = 0; n < 1000; ++n) cursor.force({1.0 + 3e-3 * n, 2.0, 3.0});
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(bad_numbers, 0);
  // The counter does count (the check above can fail).
  g_counting = true;
  { std::vector<int> v(10); }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 1);
  EXPECT_GT(cursor.cells_walked(), 10u);
}

TEST_F(Cursor, SnapshotsFromAnotherThreadAreConsistent) {
  const Eigen::Vector3d h(0.5, 0.4, 0.6);
  PlaybackFile file(write(test_util::synthetic_content(field_, h), "d.bin"));
  HapticCursor cursor(file, Scheme::kHermite);
  std::atomic<bool> done{false};
  std::atomic<int> bad{0}, seen{0};
  std::thread visual([&] {
    std::uint64_t last = 0;
    std::vector<float> pos(3 * test_util::kSyntheticViewNodes);
    while (!done.load()) {
      Snapshot s;
      cursor.snapshot(&s);
      double w = 0;
      for (double x : s.weight) w += x;
      if (s.sequence < last || std::abs(w - 1.0) > 1e-12) ++bad;
      // The snapshot's force is the force at its probe position (no torn writes).
      if (s.sequence > 0 &&
          std::abs(s.probe[0] - (1.0 + 1e-4 * static_cast<double>(s.sequence))) > 1e-9)
        ++bad;
      deform(file, s, pos);
      last = s.sequence;
      ++seen;
    }
  });
  for (int n = 1; n <= 200000; ++n) cursor.force({1.0 + 1e-4 * n, 2.0, 3.0});
  done = true;
  visual.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GT(seen.load(), 0);
}

}  // namespace
}  // namespace hapstate
