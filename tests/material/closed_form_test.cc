// Homogeneous diagonal stretches F = diag(a, b, c) against closed forms derived by hand from
// each law written in principal stretches (P_ii = dW/d lambda_i), independent of the library.
#include "material_test_util.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace hapstate {
namespace {

using Stretches = std::array<double, 3>;

// Principal first Piola-Kirchhoff stress P_ii for F = diag(s), one function per law.
Stretches linear_stress(const MaterialConstants& c, const Stretches& s) {
  const double tr = (s[0] - 1) + (s[1] - 1) + (s[2] - 1);
  Stretches p;
  for (int i = 0; i < 3; ++i) p[i] = 2 * c.mu * (s[i] - 1) + c.lambda * tr;
  return p;
}

Stretches stvk_stress(const MaterialConstants& c, const Stretches& s) {
  double tr = 0;
  for (double x : s) tr += (x * x - 1) / 2;
  Stretches p;
  for (int i = 0; i < 3; ++i) p[i] = s[i] * (c.lambda * tr + 2 * c.mu * (s[i] * s[i] - 1) / 2);
  return p;
}

// W = c10 (I1 J^-2/3 - 3) + c01 (I2 J^-4/3 - 3) + (J - 1)^2 / d1 with I1 = sum s_i^2,
// I2 = sum_{i<j} s_i^2 s_j^2, J = s0 s1 s2; dJ/ds_i = J/s_i, dI1/ds_i = 2 s_i,
// dI2/ds_i = 2 s_i (I1 - s_i^2).
Stretches mooney_stress(const MaterialConstants& c, const Stretches& s) {
  const double J = s[0] * s[1] * s[2];
  const double I1 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
  const double I2 =
      s[0] * s[0] * s[1] * s[1] + s[1] * s[1] * s[2] * s[2] + s[2] * s[2] * s[0] * s[0];
  Stretches p;
  for (int i = 0; i < 3; ++i) {
    const double dJ = J / s[i];
    const double dI1 = 2 * s[i];
    const double dI2 = 2 * s[i] * (I1 - s[i] * s[i]);
    p[i] = c.c10 * (dI1 * std::pow(J, -2.0 / 3.0) - 2.0 / 3.0 * I1 * std::pow(J, -5.0 / 3.0) * dJ) +
           c.c01 * (dI2 * std::pow(J, -4.0 / 3.0) - 4.0 / 3.0 * I2 * std::pow(J, -7.0 / 3.0) * dJ) +
           2 * (J - 1) * dJ / c.d1;
  }
  return p;
}

Stretches closed_form_stress(const MaterialConstants& c, const Stretches& s) {
  switch (c.law) {
    case Law::kLinear:
      return linear_stress(c, s);
    case Law::kStvk:
      return stvk_stress(c, s);
    case Law::kNeoHooke: {
      MaterialConstants neo = c;
      neo.c01 = 0;  // neo-Hooke is mooney without the I2 term
      return mooney_stress(neo, s);
    }
    case Law::kMooney:
      return mooney_stress(c, s);
  }
  return {};
}

Mat3 library_stress(const Material& m, const Stretches& s) {
  Mat3 P;
  m.evaluate(Eigen::Vector3d(s[0], s[1], s[2]).asDiagonal(), &P, nullptr);
  return P;
}

class ClosedForm : public ::testing::TestWithParam<test::Case> {};

TEST_P(ClosedForm, DiagonalStretchMatchesHandDerivedStress) {
  const MaterialConstants& c = GetParam().constants;
  const auto material = make_material(c);
  for (const Stretches& s : {Stretches{1.3, 0.9, 0.85}, Stretches{0.75, 1.1, 1.05},
                             Stretches{1.2, 1.2, 1.2}, Stretches{0.8, 0.8, 1.25}}) {
    const Stretches expected = closed_form_stress(c, s);
    const Mat3 P = library_stress(*material, s);
    const double scale = std::hypot(expected[0], expected[1], expected[2]);
    ASSERT_GT(scale, 1e-2 * test::kYoung);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(P(i, i), expected[i], 1e-8 * scale) << "P" << i << i;
    EXPECT_LE((P - Mat3(P.diagonal().asDiagonal())).norm(), 1e-12 * scale) << "off-diagonal";
  }
}

// Laterally free uniaxial stretch: solve P22(a, b, b) = 0 for b with a scalar Newton on the
// closed form (derivative by a central difference), then the library must give P22 = P33 = 0
// there and the closed-form P11.
TEST_P(ClosedForm, LaterallyFreeUniaxialStretch) {
  const MaterialConstants& c = GetParam().constants;
  const auto material = make_material(c);
  for (double a : {1.3, 1.1, 0.9, 0.7}) {
    auto lateral = [&](double b) { return closed_form_stress(c, {a, b, b})[1]; };
    double b = 1.0;
    for (int it = 0; it < 50 && std::abs(lateral(b)) > 1e-13 * test::kYoung; ++it) {
      const double h = 1e-6;
      b -= lateral(b) * 2 * h / (lateral(b + h) - lateral(b - h));
    }
    ASSERT_LE(std::abs(lateral(b)), 1e-9 * test::kYoung) << "scalar Newton did not converge";
    const Mat3 P = library_stress(*material, {a, b, b});
    const double p11 = closed_form_stress(c, {a, b, b})[0];
    ASSERT_GT(std::abs(p11), 1e-2 * test::kYoung);
    EXPECT_NEAR(P(0, 0), p11, 1e-8 * std::abs(p11)) << "a " << a << " b " << b;
    EXPECT_LE(std::abs(P(1, 1)), 1e-8 * std::abs(p11));
    EXPECT_LE(std::abs(P(2, 2)), 1e-8 * std::abs(p11));
  }
}

// Tiny uniaxial stretch: the constants from (E, nu) must reproduce Young's modulus and
// Poisson's ratio, P11 / (a - 1) -> E and (1 - b) / (a - 1) -> nu.
TEST_P(ClosedForm, SmallUniaxialStretchRecoversYoungAndPoisson) {
  const MaterialConstants& c = GetParam().constants;
  if (c.mu == 0) GTEST_SKIP() << "constants not derived from E, nu";
  const double young =
      9 * (c.lambda + 2 * c.mu / 3) * c.mu / (3 * (c.lambda + 2 * c.mu / 3) + c.mu);
  const double nu = c.lambda / (2 * (c.lambda + c.mu));
  ASSERT_NEAR(young, test::kYoung, 1e-9 * test::kYoung);
  const auto material = make_material(c);
  const double strain = 1e-7;
  const double a = 1 + strain;
  // Library-only Newton on b using the analytic tangent dP22/dF22 + dP22/dF33.
  double b = 1.0;
  for (int it = 0; it < 20; ++it) {
    Mat3 P;
    Mat9 A;
    material->evaluate(Eigen::Vector3d(a, b, b).asDiagonal(), &P, &A);
    b -= P(1, 1) / (A(4, 4) + A(4, 8));
  }
  const Mat3 P = library_stress(*material, {a, b, b});
  EXPECT_NEAR(P(0, 0) / strain, test::kYoung, 1e-5 * test::kYoung);
  EXPECT_NEAR((1 - b) / strain, nu, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(AllLaws, ClosedForm, ::testing::ValuesIn(test::all_cases()),
                         test::CaseName());

}  // namespace
}  // namespace hapstate
