// Frictionless sliding contact in the path solver, checked against quantities computed here
// from the state alone (an Assembler of our own, the surface triangles of the mesh):
// no surface point inside the sphere, every nodal contact force pushes, the contact forces have
// no moment about the centre (all pass through it: no tangential reaction), the felt force is
// minus the sum of the nodal contact forces and the derivative of the equilibrium energy, the
// haptic stiffness is the derivative of the felt force; a sphere smaller than the surface edges
// feels a face; the force is continuous across edges; dragging does not drag (and sticking
// does); the plate pushed from either side; a long random walk converges or says why.
#include "contact_problems.h"
#include "fem/assembler.h"
#include "solver/path_solver.h"
#include "solver/triangle_distance.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace hapstate {
namespace {

using testing::block_problem;
using testing::plate_problem;

struct SlidingCheck {
  double penetration = 0;        // max over surface triangles of (r - distance to the centre)
  double worst_pull = 0;         // max over surface nodes of -(g_n . (x_n - c)/|x_n - c|) / max |g|
  double moment = 0;             // |sum (x_n - c) x g_n| / (r |sum g_n|)
  double interior_residual = 0;  // || f || over free DOFs of nodes not on the surface [N]
  Eigen::Vector3d felt = Eigen::Vector3d::Zero();  // -sum g_n over free surface nodes [N]
};

class Independent {
 public:
  explicit Independent(const Problem& p)
      : problem_(p),
        material_(make_material(p.material)),
        assembler_(p.mesh.nodes * p.unit, p.mesh.tets, *material_) {
    on_surface_.assign(p.mesh.num_nodes(), 0);
    for (int t = 0; t < p.mesh.surface.cols(); ++t)
      for (int i = 0; i < 3; ++i) on_surface_[p.mesh.surface(i, t)] = 1;
  }

  double energy(const Eigen::VectorXd& u_m) const { return assembler_.energy(u_m); }

  SlidingCheck check(const PathSolver& solver) const {
    SlidingCheck out;
    const Eigen::Vector3d c = problem_.probe_rest + solver.probe_displacement();
    const double r = problem_.contact->radius;
    const Eigen::Matrix3Xd x = problem_.mesh.nodes + solver.displacements();
    const Triangles& tri = problem_.mesh.surface;
    for (int t = 0; t < tri.cols(); ++t) {
      const double d =
          closest_point(x.col(tri(0, t)), x.col(tri(1, t)), x.col(tri(2, t)), c).distance;
      out.penetration = std::max(out.penetration, r - d);
    }
    Eigen::VectorXd f;
    assembler_.energy_and_force(solver.state_m(), &f);
    // Nodal contact forces on the body: the load that balances the internal force.
    Eigen::Vector3d moment = Eigen::Vector3d::Zero(), sum = Eigen::Vector3d::Zero();
    double largest = 0, interior = 0;
    std::vector<std::pair<int, Eigen::Vector3d>> loads;
    for (int n = 0; n < problem_.mesh.num_nodes(); ++n) {
      bool free = true;
      for (int k = 0; k < 3; ++k)
        free = free && problem_.constraints.role[3 * n + k] == DofRole::kFree;
      if (!free) continue;
      const Eigen::Vector3d g = f.segment<3>(3 * n);  // applied load = internal force
      if (!on_surface_[n]) {
        interior += g.squaredNorm();
        continue;
      }
      moment += (x.col(n) - c).cross(g);
      sum += g;
      largest = std::max(largest, g.norm());
      loads.emplace_back(n, g);
    }
    for (const auto& [n, g] : loads)
      out.worst_pull = std::max(out.worst_pull, -g.dot((x.col(n) - c).normalized()) / largest);
    out.interior_residual = std::sqrt(interior);
    out.felt = -sum;
    out.moment = sum.norm() > 0 ? moment.norm() / (r * sum.norm()) : 0;
    return out;
  }

 private:
  const Problem& problem_;
  std::unique_ptr<Material> material_;
  Assembler assembler_;
  std::vector<char> on_surface_;
};

// The conditions of every converged frictionless state, with the tolerances docs/contact.md
// states: gaps closed to the solver's gap_tolerance x r, contact forces through the centre to 1e-6,
// nodal forces pushing (to 1e-6 of the largest), felt force = -sum of the nodal contact forces.
void expect_sliding_conditions(const SlidingCheck& c, const PathSolver& solver, double radius,
                               const std::string& where) {
  EXPECT_LE(c.penetration, solver.options().gap_tolerance * radius * (1 + 1e-6)) << where;
  EXPECT_LE(c.moment, 1e-6) << where;
  EXPECT_LE(c.worst_pull, 1e-6) << where;
  const Eigen::Vector3d felt = solver.force_felt();
  EXPECT_LE((felt - c.felt).norm(), 1e-7 * std::max(felt.norm(), 1e-12)) << where;
  EXPECT_LE(c.interior_residual, 1e-7 * std::max(felt.norm(), 1e-12)) << where;
}

TEST(SlidingContact, NoTouchMeansExactlyZeroForceAndRestShape) {
  const Problem p = block_problem(8, Friction::kNone);
  PathSolver solver(p);
  const MoveResult r = solver.move_to(Eigen::Vector3d(0.3, -0.2, -0.49));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(solver.force_felt(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(solver.state_m().isZero(0.0));
}

TEST(SlidingContact, PressingMeetsTheContactConditionsAndLeavingRestoresRest) {
  const Problem p = block_problem(8, Friction::kNone);
  const Independent truth(p);
  PathSolver solver(p);
  double last = 0;
  for (double depth : {0.05, 0.15, 0.3}) {
    const MoveResult r = solver.move_to(Eigen::Vector3d(0.1, 0.05, -0.5 - depth));
    ASSERT_TRUE(r.ok) << depth << ": " << r.reason;
    const SlidingCheck c = truth.check(solver);
    expect_sliding_conditions(c, solver, 0.8, "depth " + std::to_string(depth));
    const Eigen::Vector3d felt = solver.force_felt();
    EXPECT_GT(felt.z(), last);
    last = felt.z();
    std::printf("depth %.2f: felt (%.4g, %.4g, %.4g) N, %d multiplier re-solves, %d iterations\n",
                depth, felt.x(), felt.y(), felt.z(), r.active_set_iterations, r.iterations);
  }
  const MoveResult r = solver.move_to(Eigen::Vector3d(0.1, 0.05, 0.2));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(solver.force_felt(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(solver.state_m().isZero(0.0));
}

// Felt force = -dPi*/dc, Pi* the elastic energy of the equilibrium at centre c (the contact
// term vanishes at convergence): central differences.
TEST(SlidingContact, FeltForceIsMinusTheEnergyDerivativeAndStiffnessItsDerivative) {
  Problem p = block_problem(8, Friction::kNone);
  // Differences of equilibrium energies over 1e-4: the gaps must be closed far tighter (and a
  // stiffer penalty closes them in a few updates).
  p.solver.gap_tolerance = 1e-10;
  p.solver.contact_penalty = 1000;
  const Independent truth(p);
  PathSolver solver(p);
  const Eigen::Vector3d t0(0.13, -0.07, -0.75);
  ASSERT_TRUE(solver.move_to(t0).ok);
  const Eigen::VectorXd u0 = solver.state_m();
  const Eigen::Vector3d felt = solver.force_felt();
  Eigen::MatrixX3d du_dp;
  const Eigen::Matrix3d stiffness = solver.haptic_stiffness(&du_dp);
  const double h = 1e-4;  // mesh units
  Eigen::Matrix3d fd_stiffness;
  Eigen::MatrixX3d fd_du(u0.size(), 3);
  for (int c = 0; c < 3; ++c) {
    double e[2];
    Eigen::Vector3d f[2];
    Eigen::VectorXd u[2];
    for (int s = 0; s < 2; ++s) {
      solver.set_state(u0, t0);
      Eigen::Vector3d t = t0;
      t[c] += s == 0 ? h : -h;
      const MoveResult r = solver.move_to(t);
      ASSERT_TRUE(r.ok) << r.reason;
      e[s] = truth.energy(solver.state_m());
      f[s] = solver.force_felt();
      u[s] = solver.state_m();
    }
    fd_du.col(c) = (u[0] - u[1]) / (2 * h * p.unit);
    const double derivative = (e[0] - e[1]) / (2 * h * p.unit);  // J per metre = N
    EXPECT_NEAR(felt[c], -derivative, 1e-5 * felt.norm()) << "component " << c;
    fd_stiffness.col(c) = (f[0] - f[1]) / (2 * h);
  }
  std::printf("stiffness:\n%s\ncentral differences:\n%s\n",
              (std::ostringstream() << stiffness).str().c_str(),
              (std::ostringstream() << fd_stiffness).str().c_str());
  EXPECT_LE((stiffness - fd_stiffness).norm(), 1e-3 * stiffness.norm());
  // The displacement slopes (Hermite deformation) to the same accuracy as the stiffness.
  ASSERT_EQ(du_dp.rows(), u0.size());
  std::printf("|du/dp - central differences| / |du/dp| = %.2e\n",
              (du_dp - fd_du).norm() / du_dp.norm());
  EXPECT_LE((du_dp - fd_du).norm(), 1e-3 * du_dp.norm());
  // The sphere's curvature: pressing straight down, moving sideways tilts the force.
  EXPECT_GT(std::abs(stiffness(0, 0)), 1e-3 * std::abs(stiffness(2, 2)));
}

// A sphere of 0.3 x the mean surface edge pressed into the middle of a triangle still feels
// the surface: no node is inside it, only the face.
TEST(SlidingContact, SphereSmallerThanTheEdgesFeelsTheFace) {
  Problem p = block_problem(4, Friction::kNone);  // top-face edges 1.0 and 1.41
  double edges = 0;
  int count = 0;
  const Triangles& tri = p.mesh.surface;
  for (int t = 0; t < tri.cols(); ++t)
    for (int i = 0; i < 3; ++i) {
      edges += (p.mesh.nodes.col(tri(i, t)) - p.mesh.nodes.col(tri((i + 1) % 3, t))).norm();
      ++count;
    }
  const double radius = 0.3 * edges / count;
  // The centroid of the top-face triangle (z = 1) nearest the middle of the block.
  Eigen::Vector3d centroid(0, 0, -1);
  for (int t = 0; t < tri.cols(); ++t) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) m += p.mesh.nodes.col(tri(i, t)) / 3;
    if (std::abs(m.z() - 1) < 1e-12 &&
        (m - Eigen::Vector3d(2, 2, 1)).norm() < (centroid - Eigen::Vector3d(2, 2, 1)).norm())
      centroid = m;
  }
  ASSERT_NEAR(centroid.z(), 1.0, 1e-12);
  p.contact->radius = radius;
  p.probe_rest = centroid + Eigen::Vector3d(0, 0, radius + 0.2);
  const Independent truth(p);
  PathSolver solver(p);
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, -0.2 - 0.2 * radius));
  ASSERT_TRUE(r.ok) << r.reason;
  const Eigen::Vector3d c = p.probe_rest + solver.probe_displacement();
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    ASSERT_GT((p.mesh.nodes.col(n) - c).norm(), radius) << "a node is inside: not a face test";
  const SlidingCheck check = truth.check(solver);
  expect_sliding_conditions(check, solver, radius, "small sphere");
  EXPECT_GT(solver.force_felt().z(), 0.0);
  EXPECT_LT(solver.force_felt().head<2>().norm(), 0.2 * solver.force_felt().z());
}

// Dragging the sphere across the block at constant depth over two periods of the mesh (16 x 16
// cells): the felt force changes smoothly (no jump larger than the stiffness allows when the
// contact crosses edges and nodes); the drag, the force component against the motion, averages
// to nothing, and its ripple (the faceted P1 surface) stays small; sticking drags.
TEST(SlidingContact, DragIsSmoothAndFrictionlessWhileStickingDrags) {
  for (Friction friction : {Friction::kNone, Friction::kStick}) {
    const Problem p = block_problem(16, friction);
    PathSolver solver(p);
    const double x0 = -0.25, z = -0.7, step = 0.025;
    ASSERT_TRUE(solver.move_to(Eigen::Vector3d(x0, 0.1, z)).ok);
    double worst_drag = 0, mean_drag = 0, worst_jump_ratio = 0;
    Eigen::Vector3d last = solver.force_felt();
    const int steps = 20;
    for (int i = 1; i <= steps; ++i) {
      const MoveResult r = solver.move_to(Eigen::Vector3d(x0 + step * i, 0.1, z));
      ASSERT_TRUE(r.ok) << i << ": " << r.reason;
      const Eigen::Vector3d f = solver.force_felt();
      worst_drag = std::max(worst_drag, std::abs(f.x()) / f.z());
      mean_drag += -f.x() / f.z() / steps;  // moving +x, a drag pulls the probe back (-x)
      if (friction == Friction::kNone) {
        const Eigen::Matrix3d k = solver.haptic_stiffness();
        worst_jump_ratio = std::max(worst_jump_ratio, (f - last).norm() / (2 * k.norm() * step));
      }
      last = f;
    }
    std::printf(
        "%s: mean drag %.5f, largest tangential %.4f of the normal force, largest "
        "change %.3f of 2|K| step\n",
        friction == Friction::kNone ? "frictionless" : "stick", mean_drag, worst_drag,
        worst_jump_ratio);
    if (friction == Friction::kNone) {
      EXPECT_LE(std::abs(mean_drag), 1e-3);
      EXPECT_LE(worst_drag, 0.02);
      EXPECT_LE(worst_jump_ratio, 1.0);
    } else {
      EXPECT_GE(mean_drag, 0.1);
    }
  }
}

TEST(SlidingContact, PlatePushedFromEitherSideGivesOppositeNormalForces) {
  const Problem p = plate_problem(10, Friction::kNone);
  const Independent truth(p);
  PathSolver from_below(p), from_above(p);
  const Eigen::Vector3d target(2, 2, 0.05);
  const Eigen::Vector3d above_start(2, 2, 1.0);
  ASSERT_TRUE(from_below.move_to(target - p.probe_rest).ok);
  from_above.set_state(Eigen::VectorXd::Zero(from_above.num_dofs()), above_start - p.probe_rest);
  const MoveResult r = from_above.move_to(target - p.probe_rest);
  ASSERT_TRUE(r.ok) << r.reason;
  expect_sliding_conditions(truth.check(from_below), from_below, 0.5, "from below");
  expect_sliding_conditions(truth.check(from_above), from_above, 0.5, "from above");
  const Eigen::Vector3d f_below = from_below.force_felt(), f_above = from_above.force_felt();
  EXPECT_LT(f_below.z(), 0.0);
  EXPECT_GT(f_above.z(), 0.0);
  EXPECT_LT(f_below.head<2>().norm(), 0.01 * std::abs(f_below.z()));
  EXPECT_LT(f_above.head<2>().norm(), 0.01 * std::abs(f_above.z()));
}

TEST(SlidingContact, GapCapIsARecordedFailure) {
  Problem p = block_problem(8, Friction::kNone);
  p.solver.max_active_set_iterations = 0;
  p.solver.max_cutbacks = 1;
  PathSolver solver(p);
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, -0.7));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.failure, SolveFailure::kContactUnsettled);
  EXPECT_NE(r.reason.find("multiplier updates"), std::string::npos) << r.reason;
  EXPECT_TRUE(solver.state_m().isZero(0.0));
}

// A 1000-step random walk in and out of the block, sliding over it: every step converges or
// records why (and keeps its state); every converged state meets the contact conditions.
TEST(SlidingContact, RandomWalkConvergesOrRecordsTheReason) {
  Problem p = block_problem(6, Friction::kNone);
  p.solver.substeps = 1;
  p.solver.tolerance = 1e-9;
  const Independent truth(p);
  PathSolver solver(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.06, 0.06);
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int failures = 0, touching = 0, updates = 0;
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3d next = t + Eigen::Vector3d(step(rng), step(rng), step(rng) - 0.004);
    next.x() = std::clamp(next.x(), -1.0, 1.0);
    next.y() = std::clamp(next.y(), -1.0, 1.0);
    next.z() = std::clamp(next.z(), -0.95, -0.3);
    const Eigen::VectorXd before = solver.state_m();
    const MoveResult r = solver.move_to(next);
    if (!r.ok) {
      ++failures;
      std::printf("step %d: %s: %s\n", i, failure_name(r.failure), r.reason.c_str());
      EXPECT_FALSE(r.reason.empty()) << "step " << i;
      EXPECT_EQ(solver.state_m(), before) << "step " << i;
      continue;
    }
    t = next;
    updates += r.active_set_iterations;
    if (solver.force_felt().norm() > 0) ++touching;
    if (i % 10 == 0)
      expect_sliding_conditions(truth.check(solver), solver, 0.8, "step " + std::to_string(i));
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(touching, 500);
  std::printf("random walk: %d failures, %d steps touching, %d multiplier re-solves\n", failures,
              touching, updates);
}

}  // namespace
}  // namespace hapstate
