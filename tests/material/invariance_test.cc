// Reference state, small-strain limit and frame invariance of every law.
#include "material_test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hapstate {
namespace {

using test::Case;

class Invariance : public ::testing::TestWithParam<Case> {};

// Isotropic linear elasticity tensor mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl, written
// out entry by entry.
Mat9 linear_elasticity_tensor(double mu, double lambda) {
  Mat9 C;
  auto d = [](int a, int b) { return a == b ? 1.0 : 0.0; };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          C(i + 3 * j, k + 3 * l) =
              mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k)) + lambda * d(i, j) * d(k, l);
  return C;
}

TEST_P(Invariance, ZeroEnergyAndStressAtIdentity) {
  const auto material = make_material(GetParam().constants);
  Mat3 P;
  const double w = material->evaluate(Mat3::Identity(), &P, nullptr);
  EXPECT_LE(std::abs(w), 1e-12 * test::kYoung);
  EXPECT_LE(P.norm(), 1e-12 * test::kYoung);
}

TEST_P(Invariance, TangentAtIdentityIsLinearElasticity) {
  const MaterialConstants& c = GetParam().constants;
  if (c.mu == 0) GTEST_SKIP() << "constants not derived from E, nu";
  const auto material = make_material(c);
  Mat9 A;
  material->evaluate(Mat3::Identity(), nullptr, &A);
  const Mat9 expected = linear_elasticity_tensor(c.mu, c.lambda);
  EXPECT_LE((A - expected).norm(), 1e-10 * expected.norm()) << A;
}

TEST_P(Invariance, EnergyAndStressAreObjective) {
  const auto material = make_material(GetParam().constants);
  if (material->name() == "linear") GTEST_SKIP() << "not objective, see LinearLaw tests";
  std::mt19937 rng(42);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = test::random_deformation(rng, 0.3, true);
    const Mat3 Q = test::random_rotation(rng);
    Mat3 P, P_rotated;
    const double w = material->evaluate(F, &P, nullptr);
    const double w_rotated = material->evaluate(Q * F, &P_rotated, nullptr);
    ASSERT_GT(w, 1e-3 * test::kYoung);
    EXPECT_NEAR(w_rotated, w, 1e-11 * w);
    EXPECT_LE((P_rotated - Q * P).norm(), 1e-11 * P.norm());
  }
}

TEST_P(Invariance, InvertedElementsGiveInfiniteEnergyWithoutNan) {
  const auto material = make_material(GetParam().constants);
  const Mat3 reflected = Eigen::Vector3d(-1.0, 1.1, 0.9).asDiagonal();
  Mat3 flat = Mat3::Identity();
  flat(2, 2) = 0.0;
  for (const Mat3& F : {reflected, flat}) {
    Mat3 P;
    Mat9 A;
    const double w = material->evaluate(F, &P, &A);
    EXPECT_TRUE(P.allFinite());
    EXPECT_TRUE(A.allFinite());
    if (material->requires_positive_jacobian()) {
      EXPECT_TRUE(std::isinf(w) && w > 0);
      EXPECT_TRUE(std::isinf(material->energy(F)));
      EXPECT_EQ(P.norm(), 0.0);
      EXPECT_EQ(A.norm(), 0.0);
    } else {
      EXPECT_TRUE(std::isfinite(w));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllLaws, Invariance, ::testing::ValuesIn(test::all_cases()),
                         test::CaseName());

Mat3 rotation_about_z(double theta) {
  return Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The geometrically linear law sees a finite rigid rotation as strain:
// eps = diag(cos t - 1, cos t - 1, 0), so W = 2 (mu + lambda) (1 - cos t)^2 > 0.
TEST(LinearLaw, FiniteRotationProducesSpuriousEnergy) {
  const MaterialConstants c = constants_from_young_poisson(Law::kLinear, test::kYoung, 0.3);
  const auto material = make_material(c);
  for (double theta : {0.5, 0.1, 1e-2}) {
    const double expected = 2.0 * (c.mu + c.lambda) * std::pow(1.0 - std::cos(theta), 2);
    EXPECT_NEAR(material->energy(rotation_about_z(theta)), expected, 1e-9 * expected);
  }
  EXPECT_GT(material->energy(rotation_about_z(0.5)), 1e-2 * test::kYoung);
}

// ...but is invariant under infinitesimal rotations F -> F + Omega, Omega skew.
TEST(LinearLaw, InvariantUnderInfinitesimalRotation) {
  const auto material =
      make_material(constants_from_young_poisson(Law::kLinear, test::kYoung, 0.3));
  std::mt19937 rng(7);
  const Mat3 F = test::random_deformation(rng, 0.1, false);
  Mat3 omega;
  omega << 0, -0.3, 0.2, 0.3, 0, -0.1, -0.2, 0.1, 0;
  Mat3 P, P_spun;
  const double w = material->evaluate(F, &P, nullptr);
  const double w_spun = material->evaluate(F + omega, &P_spun, nullptr);
  EXPECT_NEAR(w_spun, w, 1e-12 * w);
  EXPECT_LE((P_spun - P).norm(), 1e-12 * P.norm());
  EXPECT_LE((P - P.transpose()).norm(), 1e-12 * P.norm()) << "linear P is symmetric";
}

}  // namespace
}  // namespace hapstate
