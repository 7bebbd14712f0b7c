// P and A of every law against finite differences of W and P at random deformation gradients.
#include "material_test_util.h"

#include <gtest/gtest.h>

namespace hapstate {
namespace {

using test::Case;

constexpr double kStep = 1e-3;          // FD step on entries of F (4th-order stencil)
constexpr double kRelTolerance = 1e-6;  // relative to the norm of the analytic quantity

class Derivatives : public ::testing::TestWithParam<Case> {};

TEST_P(Derivatives, StressAndTangentMatchFiniteDifferences) {
  const auto material = make_material(GetParam().constants);
  int checked = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    for (double strain : {0.05, 0.15, 0.3}) {
      std::mt19937 rng(seed);
      const Mat3 F = test::random_deformation(rng, strain, seed % 2 == 0);
      SCOPED_TRACE("seed " + std::to_string(seed) + " strain " + std::to_string(strain) + " det " +
                   std::to_string(F.determinant()));
      Mat3 P;
      Mat9 A;
      const double w = material->evaluate(F, &P, &A);
      ASSERT_DOUBLE_EQ(w, material->energy(F));

      Mat3 P_fd;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          P_fd(i, j) = test::central_difference([&](const Mat3& G) { return material->energy(G); },
                                                F, i, j, kStep);
      ASSERT_GT(P.norm(), 1e-3 * test::kYoung * strain) << "analytic P is trivially small";
      EXPECT_LE((P - P_fd).norm(), kRelTolerance * P.norm()) << "P\n" << P << "\nFD\n" << P_fd;

      Mat9 A_fd;
      for (int l = 0; l < 3; ++l)
        for (int k = 0; k < 3; ++k) {
          const Mat3 column = test::central_difference(
              [&](const Mat3& G) {
                Mat3 Pg;
                material->evaluate(G, &Pg, nullptr);
                return Pg;
              },
              F, k, l, kStep);
          A_fd.col(k + 3 * l) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(column.data());
        }
      ASSERT_GT(A.norm(), 1e-2 * test::kYoung) << "analytic A is trivially small";
      EXPECT_LE((A - A_fd).norm(), kRelTolerance * A.norm());
      EXPECT_LE((A - A.transpose()).norm(), 1e-12 * A.norm()) << "A not symmetric";

      Mat3 P_only;
      material->evaluate(F, &P_only, nullptr);
      EXPECT_EQ(P_only, P) << "P must not depend on whether A is requested";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 18);
}

INSTANTIATE_TEST_SUITE_P(AllLaws, Derivatives, ::testing::ValuesIn(test::all_cases()),
                         test::CaseName());

}  // namespace
}  // namespace hapstate
