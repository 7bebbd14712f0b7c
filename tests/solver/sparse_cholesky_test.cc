// The sparse Cholesky factorisation's solves: double precision against the matrix itself, and
// the single-precision solve (the conjugate gradients' preconditioner) against the double one.
#include "solver/sparse_cholesky.h"
#include "fem/assembler.h"
#include "material/material.h"
#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace hapstate {
namespace {

// A neo-Hooke block (nu = 0.45) sheared by 5 %, held at x = 0 (identity rows and columns): a
// tangent like the expansion's, with a condition number in the thousands.
struct Block {
  Mesh mesh = make_box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.06, 0.03, 0.02), 18, 9, 6);
  std::unique_ptr<Material> material =
      make_material(constants_from_young_poisson(Law::kNeoHooke, 5000, 0.45));
  std::unique_ptr<Assembler> assembler;
  std::vector<double> k;
  Eigen::VectorXd b;

  Block() {
    assembler = std::make_unique<Assembler>(mesh.nodes, mesh.tets, *material);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * mesh.num_nodes()), f;
    for (int n = 0; n < mesh.num_nodes(); ++n) u[3 * n + 1] = 0.05 * mesh.nodes(0, n);
    assembler->energy_force_tangent(u, &f, &k);
    const SymmetricPattern& p = assembler->pattern();
    auto held = [&](int dof) { return mesh.nodes(0, dof / 3) < 1e-9; };
    for (int col = 0; col < p.n; ++col)
      for (int e = p.col_ptr[col]; e < p.col_ptr[col + 1]; ++e)
        if (held(p.row_idx[e]) || held(col)) k[e] = p.row_idx[e] == col ? 1.0 : 0.0;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-1, 1);
    b.resize(p.n);
    for (int i = 0; i < p.n; ++i) b[i] = held(i) ? 0.0 : d(rng);
  }
};

double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(SparseCholesky, SolvesTheMatrixInDoublePrecision) {
  Block block;
  for (auto method : {SparseCholesky::Method::kSimplicial, SparseCholesky::Method::kSupernodal}) {
    SparseCholesky chol(block.assembler->pattern(), method);
    ASSERT_TRUE(chol.factorize(block.k));
    Eigen::VectorXd x, ax;
    chol.solve(block.b, &x);
    symmetric_multiply(block.assembler->pattern(), block.k, x, &ax);
    EXPECT_LT(relative_difference(ax, block.b), 1e-10) << chol.method();  // measured 1.1e-12
  }
}

// Rounding the factor to float changes the solve by about its condition number times float's
// epsilon (6e-8): measured 3.6e-7 here. A preconditioner needs no more; the solve reads half
// the bytes (factor_bytes counts the double factor).
TEST(SparseCholesky, SinglePrecisionSolveIsCloseToTheDoubleOne) {
  Block block;
  SparseCholesky chol(block.assembler->pattern(), SparseCholesky::Method::kSupernodal);
  ASSERT_STREQ(chol.method(), "supernodal");
  ASSERT_TRUE(chol.factorize(block.k));
  Eigen::VectorXd x, y;
  chol.solve(block.b, &x);
  chol.solve_single(block.b, &y);
  const double difference = relative_difference(y, x);
  EXPECT_GT(difference, 0.0);  // it is rounded
  EXPECT_LT(difference, 1e-5);
  // A new factorisation is rounded again: the solve follows the new matrix.
  std::vector<double> scaled = block.k;
  for (double& v : scaled) v *= 2;
  ASSERT_TRUE(chol.factorize(scaled));
  Eigen::VectorXd y2;
  chol.solve_single(block.b, &y2);
  EXPECT_LT(relative_difference(2 * y2, x), 1e-5);
  std::printf("[ info ] single against double precision: %.2e, after refactorising %.2e\n",
              difference, relative_difference(2 * y2, x));
}

TEST(SparseCholesky, SinglePrecisionSolveOfASimplicialFactorIsTheDoubleOne) {
  Block block;
  SparseCholesky chol(block.assembler->pattern(), SparseCholesky::Method::kSimplicial);
  ASSERT_TRUE(chol.factorize(block.k));
  Eigen::VectorXd x, y;
  chol.solve(block.b, &x);
  chol.solve_single(block.b, &y);
  EXPECT_EQ(x, y);
}

}  // namespace
}  // namespace hapstate
