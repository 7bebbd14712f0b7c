// The path solver on synthetic box meshes: homogeneous uniaxial stretch against the law's
// closed form, quadratic Newton convergence, cut-back of a huge step, failure reporting, and
// the haptic stiffness against finite differences of the felt force.
#include "solver/path_solver.h"
#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hapstate {
namespace {

// Unit cube (mesh units, unit = 0.01 m) with symmetry supports: x held on xmin, y on ymin,
// z on zmin; the xmax face is the probe and follows it in x only.
Problem uniaxial_problem(Law law) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2, 2, 2);
  p.unit = 0.01;
  p.material = constants_from_young_poisson(law, 1e4, 0.3);
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  for (int n : p.mesh.groups.at("xmin")) p.constraints.role[3 * n + 0] = DofRole::kFixed;
  for (int n : p.mesh.groups.at("ymin")) p.constraints.role[3 * n + 1] = DofRole::kFixed;
  for (int n : p.mesh.groups.at("zmin")) p.constraints.role[3 * n + 2] = DofRole::kFixed;
  p.constraints.probe_nodes = p.mesh.groups.at("xmax");
  p.constraints.probe_components = {true, false, false};
  for (int n : p.constraints.probe_nodes) p.constraints.role[3 * n] = DofRole::kProbe;
  p.probe_rest = Eigen::Vector3d(1, 0.5, 0.5);
  p.solver.tolerance = 1e-10;
  return p;
}

// Cantilever 10 x 1 x 1 (unit = 0.01 m) clamped at x = 0, the far-end centre node grabbed.
Problem cantilever_problem(Law law) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 1, 1), 10, 2, 2);
  p.unit = 0.01;
  p.material = constants_from_young_poisson(law, 1e5, 0.3);
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  for (int n : p.mesh.groups.at("xmin"))
    for (int c = 0; c < 3; ++c) p.constraints.role[3 * n + c] = DofRole::kFixed;
  int tip = -1;
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    if ((p.mesh.nodes.col(n) - Eigen::Vector3d(10, 0.5, 0.5)).norm() < 1e-9) tip = n;
  p.constraints.probe_nodes = {tip};
  for (int c = 0; c < 3; ++c) p.constraints.role[3 * tip + c] = DofRole::kProbe;
  p.probe_rest = p.mesh.nodes.col(tip);
  return p;
}

// Uniaxial, laterally free stress P11 for stretch a along x: find the lateral stretch b with
// P22(diag(a, b, b)) = 0 by a scalar Newton iteration on the material law.
double uniaxial_p11(const Material& m, double a) {
  double b = 1.0;
  for (int it = 0; it < 100; ++it) {
    const auto p22 = [&](double bb) {
      Mat3 p;
      m.evaluate(Eigen::Vector3d(a, bb, bb).asDiagonal(), &p, nullptr);
      return p(1, 1);
    };
    const double h = 1e-7;
    const double slope = (p22(b + h) - p22(b - h)) / (2 * h);
    const double step = p22(b) / slope;
    b -= step;
    if (std::abs(step) < 1e-15) break;
  }
  Mat3 p;
  m.evaluate(Eigen::Vector3d(a, b, b).asDiagonal(), &p, nullptr);
  return p(0, 0);
}

TEST(PathSolver, UniaxialStretchMatchesClosedForm) {
  for (Law law : {Law::kStvk, Law::kNeoHooke, Law::kMooney}) {
    const Problem problem = uniaxial_problem(law);
    const auto material = make_material(problem.material);
    PathSolver solver(problem);
    for (double stretch : {1.3, 0.8}) {
      solver.reset();
      const MoveResult r = solver.move_to(Eigen::Vector3d(stretch - 1.0, 0, 0));
      ASSERT_TRUE(r.ok) << law_name(law) << ": " << r.reason;
      // Force the user feels = -(force the probe applies) = -P11 * area (area 1 cm^2).
      const double expected = -uniaxial_p11(*material, stretch) * 1e-4;
      const Eigen::Vector3d felt = solver.force_felt();
      EXPECT_NEAR(felt.x(), expected, 1e-8 * std::abs(expected)) << law_name(law) << " " << stretch;
      EXPECT_NEAR(felt.y(), 0.0, 1e-10);
      // Stretching pulls the user's hand back (-x), compressing pushes it out (+x).
      EXPECT_EQ(felt.x() < 0, stretch > 1) << law_name(law);
    }
  }
}

TEST(PathSolver, NewtonConvergesQuadratically) {
  Problem problem = cantilever_problem(Law::kNeoHooke);
  problem.solver.substeps = 1;
  problem.solver.tolerance = 1e-12;
  problem.solver.absolute_tolerance = 0;
  PathSolver solver(problem);
  solver.set_algorithm(SolverAlgorithm::kReference);  // full Newton: a factorisation per iteration
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 1.0, 0.5));
  ASSERT_TRUE(r.ok) << r.reason;
  const auto& h = r.residual_history;
  ASSERT_GE(h.size(), 3u);
  // Find two consecutive iterations in the asymptotic range (relative residual between
  // 1e-1 and 1e-11): the error exponent log(e_{k+1}) / log(e_k) must be close to 2.
  bool checked = false;
  for (std::size_t k = 1; k + 1 < h.size(); ++k) {
    const double e0 = h[k] / h[0], e1 = h[k + 1] / h[0];
    if (e0 < 1e-1 && e1 > 1e-11) {
      EXPECT_GT(std::log(e1) / std::log(e0), 1.7) << "iteration " << k;
      checked = true;
    }
  }
  EXPECT_TRUE(checked) << "no iteration pair in the asymptotic range; history size " << h.size();
  EXPECT_EQ(r.factorisations, r.iterations);
}

TEST(PathSolver, HugeStepIsCutBackAndConverges) {
  Problem problem = cantilever_problem(Law::kNeoHooke);
  problem.solver.substeps = 1;
  problem.solver.max_iterations = 8;
  PathSolver solver(problem);
  // 50 % of the beam length sideways and 20 % back in one move.
  const MoveResult r = solver.move_to(Eigen::Vector3d(-2.0, 5.0, 0));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_GT(r.cutbacks, 0);
  // The result equals a careful solve with many sub-steps.
  Problem careful = cantilever_problem(Law::kNeoHooke);
  careful.solver.substeps = 20;
  PathSolver reference(careful);
  ASSERT_TRUE(reference.move_to(Eigen::Vector3d(-2.0, 5.0, 0)).ok);
  EXPECT_LE((solver.force_felt() - reference.force_felt()).norm(),
            1e-6 * reference.force_felt().norm());
}

// A move that fails as one move (no cut-back allowed, few Newton iterations) converges split
// into equal moves (PathSolver::move_to's fallback), at the same equilibrium as a careful solve.
TEST(PathSolver, FailedMoveConvergesSplitIntoPieces) {
  Problem problem = cantilever_problem(Law::kNeoHooke);
  problem.solver.substeps = 1;
  problem.solver.max_cutbacks = 0;
  problem.solver.max_iterations = 6;
  PathSolver solver(problem);
  const MoveResult r = solver.move_to(Eigen::Vector3d(-2.0, 5.0, 0));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_GT(r.split_pieces, 1);
  EXPECT_EQ(r.failure, SolveFailure::kNone);
  EXPECT_TRUE(r.reason.empty());
  EXPECT_EQ(solver.probe_displacement(), Eigen::Vector3d(-2.0, 5.0, 0));
  Problem careful = cantilever_problem(Law::kNeoHooke);
  careful.solver.substeps = 20;
  PathSolver reference(careful);
  ASSERT_TRUE(reference.move_to(Eigen::Vector3d(-2.0, 5.0, 0)).ok);
  EXPECT_EQ(reference.move_to(Eigen::Vector3d(-2.0, 5.0, 0)).split_pieces, 1);
  EXPECT_LE((solver.force_felt() - reference.force_felt()).norm(),
            1e-6 * reference.force_felt().norm());
}

TEST(PathSolver, ImpossibleMoveReportsReasonAndKeepsState) {
  Problem problem = cantilever_problem(Law::kNeoHooke);
  problem.solver.max_cutbacks = 2;
  problem.solver.max_iterations = 3;
  problem.solver.substeps = 1;
  PathSolver solver(problem);
  ASSERT_TRUE(solver.move_to(Eigen::Vector3d(0, 0.5, 0)).ok);
  const Eigen::VectorXd before = solver.state_m();
  // Push the tip through the clamped end: hopeless with 3 iterations and 2 cut-backs.
  const MoveResult r = solver.move_to(Eigen::Vector3d(-12.0, 0.5, 0));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure, SolveFailure::kNone);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_EQ(solver.state_m(), before);
  EXPECT_EQ(solver.probe_displacement(), Eigen::Vector3d(0, 0.5, 0));
}

TEST(PathSolver, HapticStiffnessAndDisplacementSlopesAreDerivativesOfTheEquilibrium) {
  for (Law law : {Law::kStvk, Law::kNeoHooke, Law::kMooney}) {
    Problem problem = cantilever_problem(law);
    problem.solver.tolerance = 1e-12;
    PathSolver solver(problem);
    const Eigen::Vector3d t(0.3, 2.0, -1.0);
    ASSERT_TRUE(solver.move_to(t).ok);
    Eigen::MatrixX3d du_dp;
    const Eigen::Matrix3d k = solver.haptic_stiffness(&du_dp);
    const Eigen::VectorXd u0 = solver.state_m();
    Eigen::Matrix3d fd;
    Eigen::MatrixX3d fd_du(u0.size(), 3);
    const double h = 1e-4;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d f[2];
      Eigen::VectorXd u[2];
      for (int s = 0; s < 2; ++s) {
        solver.set_state(u0, t);
        ASSERT_TRUE(solver.move_to(t + (s ? h : -h) * Eigen::Vector3d::Unit(c)).ok);
        f[s] = solver.force_felt();
        u[s] = solver.state_m();
      }
      fd.col(c) = (f[1] - f[0]) / (2 * h);
      fd_du.col(c) = (u[1] - u[0]) / (2 * h * problem.unit);  // metres per metre
    }
    EXPECT_LE((fd - k).norm(), 1e-5 * k.norm()) << law_name(law) << "\n" << k << "\n" << fd;
    // d u / d p: the grabbed DOFs move with the probe (1), the others by the equilibrium.
    ASSERT_EQ(du_dp.rows(), u0.size());
    EXPECT_LE((fd_du - du_dp).norm(), 1e-5 * du_dp.norm()) << law_name(law);
    EXPECT_GT(du_dp.norm(), 1.0) << law_name(law);
    // Pulling a node out of a stable body: the felt force opposes the motion.
    EXPECT_LT(k.trace(), 0) << law_name(law);
  }
}

}  // namespace
}  // namespace hapstate

namespace hapstate {
namespace {

// The fast algorithm reaches the same equilibrium as full Newton with fixed sub-steps, with
// fewer factorisations than iterations (inexact Newton preconditions with them).
TEST(PathSolver, FastAlgorithmEqualsReferenceWithFewerFactorisations) {
  for (Law law : {Law::kNeoHooke, Law::kStvk, Law::kMooney}) {
    Problem problem = cantilever_problem(law);
    problem.solver.tolerance = 1e-12;
    PathSolver fast(problem), reference(problem);
    reference.set_algorithm(SolverAlgorithm::kReference);
    const Eigen::Vector3d move(0, 1.0, 0.5);
    const MoveResult a = fast.move_to(move), b = reference.move_to(move);
    ASSERT_TRUE(a.ok && b.ok) << law_name(law) << ": " << a.reason << b.reason;
    EXPECT_LE((fast.force_felt() - reference.force_felt()).norm(),
              1e-9 * reference.force_felt().norm())
        << law_name(law);
    EXPECT_LE((fast.displacements() - reference.displacements()).norm(),
              1e-9 * reference.displacements().norm())
        << law_name(law);
    EXPECT_LT(a.factorisations, b.factorisations) << law_name(law);
    EXPECT_LT(a.factorisations, a.iterations) << law_name(law);
    std::printf(
        "[ info ] %s: fast %d factorisations / %d iterations / %d sub-steps, reference %d "
        "/ %d / %d\n",
        std::string(law_name(law)).c_str(), a.factorisations, a.iterations, a.substeps,
        b.factorisations, b.iterations, b.substeps);
  }
}

// Every direction of a configuration's expansion starts from the same state: the fast
// algorithm keeps the predictor's factorisation there and the next move from that state reuses
// it, landing bitwise where a solver without the kept factorisation lands, one factorisation
// cheaper.
TEST(PathSolver, FastAlgorithmReusesTheStartStatesFactorisation) {
  Problem problem = cantilever_problem(Law::kNeoHooke);
  PathSolver warm(problem);
  ASSERT_TRUE(warm.move_to(Eigen::Vector3d(0, 0.5, 0)).ok);
  const Eigen::VectorXd u0 = warm.state_m();
  const Eigen::Vector3d t0 = warm.probe_displacement();
  ASSERT_TRUE(warm.move_to(t0 + Eigen::Vector3d(0.2, 0, 0)).ok);  // keeps the factor at u0
  warm.set_state(u0, t0);
  const Eigen::Vector3d target = t0 + Eigen::Vector3d(0, 0.2, 0.1);
  const MoveResult reused = warm.move_to(target);
  PathSolver fresh(problem);
  fresh.set_state(u0, t0);
  const MoveResult full = fresh.move_to(target);
  ASSERT_TRUE(reused.ok && full.ok) << reused.reason << full.reason;
  EXPECT_EQ(reused.factorisations, full.factorisations - 1);
  EXPECT_EQ(reused.iterations, full.iterations);
  EXPECT_TRUE((warm.state_m().array() == fresh.state_m().array()).all());
  EXPECT_EQ(warm.force_felt(), fresh.force_felt());
}

// St. Venant-Kirchhoff loses stability in strong compression (the uniaxial limit point is at
// stretch 1/sqrt(3)): the free-DOF tangent turns indefinite and the solver must fall back to the
// PSD-projected tangent for its search directions instead of failing or crashing.
TEST(PathSolver, IndefiniteTangentFallsBackAndReportsOrConverges) {
  // Confined compression: y and z held everywhere, so the axial tangent of the homogeneous
  // state is (lambda + 2 mu)(3 s^2 - 1)/2, negative below the stretch s = 1/sqrt(3).
  Problem problem = uniaxial_problem(Law::kStvk);
  for (int n = 0; n < problem.mesh.num_nodes(); ++n)
    for (int c : {1, 2}) problem.constraints.role[3 * n + c] = DofRole::kFixed;
  problem.solver.substeps = 8;
  PathSolver solver(problem);
  solver.set_algorithm(SolverAlgorithm::kReference);  // 8 fixed sub-steps into the limit point
  const MoveResult r = solver.move_to(Eigen::Vector3d(-0.55, 0, 0));
  std::printf("psd fallbacks %lld, ok %d, reason '%s'\n", solver.timings().psd_fallbacks, r.ok,
              r.reason.c_str());
  EXPECT_GT(solver.timings().psd_fallbacks, 0);
  if (r.ok) {
    EXPECT_LE(r.residual, 1e-6 * solver.force_felt().norm() + 1e-9);
  } else {
    EXPECT_NE(r.failure, SolveFailure::kNone);
    EXPECT_FALSE(r.reason.empty());
  }
}

}  // namespace
}  // namespace hapstate
