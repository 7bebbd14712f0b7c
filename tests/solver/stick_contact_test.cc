// The contact probe in the path solver, checked against independent truths computed here from
// the state (an Assembler of our own): touched nodes lie on the sphere, no other surface node
// is inside it, every reaction pushes, the felt force is minus the sum of the reactions and the
// derivative of the equilibrium energy; no touch gives exactly zero force and the rest shape;
// the plate pushed from either side to the same centre gives opposite normal forces.
#include "contact_problems.h"
#include "fem/assembler.h"
#include "solver/path_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace hapstate {
namespace {

using testing::block_problem;
using testing::plate_problem;

// What the state tells independently of the solver's bookkeeping.
struct ContactCheck {
  double off_sphere = 0;     // max | |x_n - c| - r | over touched nodes (mesh units)
  double penetration = 0;    // max (r - |x_n - c|) over untouched candidates, 0 if none inside
  double worst_pull = 0;     // max over touched nodes of -(h_n . normal) / max |h| (0: all push)
  double free_residual = 0;  // || f_free || [N]
  Eigen::Vector3d reaction_sum = Eigen::Vector3d::Zero();  // -sum of h_n over touched nodes [N]
};

class Independent {
 public:
  explicit Independent(const Problem& p)
      : problem_(p),
        material_(make_material(p.material)),
        assembler_(p.mesh.nodes * p.unit, p.mesh.tets, *material_) {}

  double energy(const Eigen::VectorXd& u_m) const { return assembler_.energy(u_m); }

  ContactCheck check(const PathSolver& solver) const {
    ContactCheck out;
    const Eigen::Vector3d centre = problem_.probe_rest + solver.probe_displacement();
    const double r = problem_.contact->radius;
    const std::vector<int> touched = solver.touched_nodes();
    const Eigen::Matrix3Xd x = problem_.mesh.nodes + solver.displacements();
    Eigen::VectorXd f;
    assembler_.energy_and_force(solver.state_m(), &f);
    double largest = 0;
    for (int n : touched) largest = std::max(largest, f.segment<3>(3 * n).norm());
    for (int n : touched) {
      const Eigen::Vector3d ray = x.col(n) - centre;
      out.off_sphere = std::max(out.off_sphere, std::abs(ray.norm() - r));
      const double push = f.segment<3>(3 * n).dot(ray.normalized());
      out.worst_pull = std::max(out.worst_pull, -push / largest);
      out.reaction_sum -= f.segment<3>(3 * n);
    }
    for (int n : problem_.contact->candidates) {
      if (std::binary_search(touched.begin(), touched.end(), n)) continue;
      out.penetration = std::max(out.penetration, r - (x.col(n) - centre).norm());
    }
    double s = 0;
    for (int d = 0; d < f.size(); ++d) {
      const bool fixed = problem_.constraints.role[d] == DofRole::kFixed;
      const bool held = std::binary_search(touched.begin(), touched.end(), d / 3);
      if (!fixed && !held) s += f[d] * f[d];
    }
    out.free_residual = std::sqrt(s);
    return out;
  }

 private:
  const Problem& problem_;
  std::unique_ptr<Material> material_;
  Assembler assembler_;
};

// The contact conditions every converged state must meet (tolerances of contact_set.h).
void expect_contact_conditions(const ContactCheck& c, double radius, const std::string& where) {
  EXPECT_LT(c.off_sphere, 1e-9 * radius) << where;
  EXPECT_LE(c.penetration, kPenetrationTolerance * radius * (1 + 1e-9)) << where;
  EXPECT_LE(c.worst_pull, kAdhesionTolerance * (1 + 1e-9)) << where;
}

TEST(ContactProbe, NoTouchMeansExactlyZeroForceAndRestShape) {
  const Problem p = block_problem();
  PathSolver solver(p);
  // Down to 0.01 above the top face (z = 1): nothing touched.
  const MoveResult r = solver.move_to(Eigen::Vector3d(0.3, -0.2, -0.49));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(solver.touched_nodes().empty());
  EXPECT_EQ(solver.force_felt(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(solver.state_m().isZero(0.0));
}

TEST(ContactProbe, PressingTheBlockPushesBackAlongTheNormalAndLeavingRestoresRest) {
  const Problem p = block_problem();
  const Independent truth(p);
  PathSolver solver(p);
  double last_force = 0;
  for (double depth : {0.1, 0.2, 0.3}) {
    const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, -0.5 - depth));
    ASSERT_TRUE(r.ok) << depth << ": " << r.reason;
    const ContactCheck c = truth.check(solver);
    expect_contact_conditions(c, 0.8, "depth " + std::to_string(depth));
    EXPECT_LT(c.free_residual, 1e-8 * c.reaction_sum.norm());
    const Eigen::Vector3d felt = solver.force_felt();
    EXPECT_TRUE(felt.isApprox(c.reaction_sum, 1e-12));
    // The body pushes the probe up (+z, the outward normal of the top face), more the deeper;
    // sideways only what the mesh breaks of the symmetry: every cell's 6 tets share the
    // (1, 1, 1) diagonal, which tilts a node's stiffness (12 % of the normal force here with one
    // node touched, 8 % on 16 x 16 cells).
    EXPECT_GT(felt.z(), last_force);
    EXPECT_LT(std::hypot(felt.x(), felt.y()), 0.15 * felt.z());
    EXPECT_GE(solver.touched_nodes().size(), 1u);
    last_force = felt.z();
  }
  // Back up and away: every node lets go, the body springs back exactly.
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, 0.2));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(solver.touched_nodes().empty());
  EXPECT_EQ(solver.force_felt(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(solver.state_m().isZero(0.0));
}

// With one node touched, the contact state is the grab problem of that node at the same
// displacement (grab is checked against CalculiX in tests/ccx): same force, same field.
TEST(ContactProbe, OneTouchedNodeEqualsGrabbingIt) {
  const Problem p = block_problem();
  PathSolver contact(p);
  ASSERT_TRUE(contact.move_to(Eigen::Vector3d(0, 0, -0.6)).ok);  // 0.1 into the top face
  ASSERT_EQ(contact.touched_nodes().size(), 1u);
  const int node = contact.touched_nodes()[0];
  EXPECT_EQ(p.mesh.nodes.col(node), Eigen::Vector3d(2, 2, 1));
  const Eigen::Vector3d u_node = contact.displacements().col(node);
  EXPECT_NEAR(u_node.z(), -0.1, 1e-12);  // anchored straight below the centre

  Problem grab = p;
  grab.contact.reset();
  grab.probe_rest = p.mesh.nodes.col(node);
  grab.constraints.probe_nodes = {node};
  for (int c = 0; c < 3; ++c) grab.constraints.role[3 * node + c] = DofRole::kProbe;
  PathSolver grabbed(grab);
  ASSERT_TRUE(grabbed.move_to(u_node).ok);
  const Eigen::Vector3d f = contact.force_felt();
  EXPECT_LE((grabbed.force_felt() - f).norm(), 1e-8 * f.norm());
  EXPECT_LE((grabbed.state_m() - contact.state_m()).lpNorm<Eigen::Infinity>(),
            1e-8 * contact.state_m().lpNorm<Eigen::Infinity>());
}

// With the touched set and anchors fixed, the touched nodes translate with the centre c and the
// felt force is -d(equilibrium energy)/dc: central differences, set unchanged by the small moves.
TEST(ContactProbe, FeltForceIsMinusTheEnergyDerivative) {
  const Problem p = block_problem();
  const Independent truth(p);
  PathSolver solver(p);
  const Eigen::Vector3d t0(0.05, -0.03, -0.75);
  ASSERT_TRUE(solver.move_to(t0).ok);
  const std::vector<int> touched = solver.touched_nodes();
  const Eigen::VectorXd u0 = solver.state_m();
  const Eigen::Vector3d felt = solver.force_felt();
  const double h = 1e-5;  // mesh units
  for (int c = 0; c < 3; ++c) {
    double e[2];
    for (int s = 0; s < 2; ++s) {
      solver.set_state(u0, t0, touched);
      Eigen::Vector3d t = t0;
      t[c] += s == 0 ? h : -h;
      const MoveResult r = solver.move_to(t);
      ASSERT_TRUE(r.ok) << r.reason;
      ASSERT_EQ(solver.touched_nodes(), touched) << "component " << c;
      e[s] = truth.energy(solver.state_m());
    }
    const double derivative = (e[0] - e[1]) / (2 * h * p.unit);  // J per metre = N
    EXPECT_NEAR(felt[c], -derivative, 1e-5 * felt.norm()) << "component " << c;
  }
}

// The paper's plate: the same probe centre, reached from below and from above, holds two
// different deformations, with opposite forces along the plate normal.
TEST(ContactProbe, PlatePushedFromEitherSideGivesOppositeNormalForces) {
  Problem p = plate_problem();
  const Independent truth(p);
  PathSolver from_below(p);
  PathSolver from_above(p);
  // The centre (2, 2, 0.05) is inside the plate's rest volume: only reachable by pushing it.
  const Eigen::Vector3d target(2, 2, 0.05);
  const Eigen::Vector3d above_start(2, 2, 1.0);
  ASSERT_TRUE(from_below.move_to(target - p.probe_rest).ok);
  from_above.set_state(Eigen::VectorXd::Zero(from_above.num_dofs()), above_start - p.probe_rest);
  for (int step = 1; step <= 4; ++step) {
    const MoveResult r =
        from_above.move_to(above_start + (target - above_start) * step / 4.0 - p.probe_rest);
    ASSERT_TRUE(r.ok) << r.reason;
  }
  const Eigen::Vector3d f_below = from_below.force_felt();
  const Eigen::Vector3d f_above = from_above.force_felt();
  expect_contact_conditions(truth.check(from_below), 0.5, "from below");
  expect_contact_conditions(truth.check(from_above), 0.5, "from above");
  EXPECT_LT(f_below.z(), 0.0);  // the plate, bent up, pushes the probe back down
  EXPECT_GT(f_above.z(), 0.0);
  // In-plane components: only the tets' diagonal split (see the block test).
  EXPECT_LT(f_below.head<2>().norm(), 0.15 * std::abs(f_below.z()));
  EXPECT_LT(f_above.head<2>().norm(), 0.15 * std::abs(f_above.z()));
  // Opposite deformations: the plate centre went up from below, down from above.
  const Eigen::Vector3d mid(2, 2, 0.1);
  int top = 0;
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    if ((p.mesh.nodes.col(n) - mid).norm() < 1e-9) top = n;
  EXPECT_GT(from_below.displacements()(2, top), 0.3);
  EXPECT_LT(from_above.displacements()(2, top), -0.3);
}

// The active-set cap: with no iteration allowed, a move that has to touch the body fails with
// the reason recorded and the state kept.
TEST(ContactProbe, ActiveSetCapIsARecordedFailure) {
  Problem p = block_problem();
  p.solver.max_active_set_iterations = 0;
  p.solver.max_cutbacks = 1;
  PathSolver solver(p);
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, -0.7));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.failure, SolveFailure::kContactUnsettled);
  EXPECT_NE(r.reason.find("the touched set still changed after 0 active-set iterations"),
            std::string::npos)
      << r.reason;
  EXPECT_TRUE(solver.state_m().isZero(0.0));
  EXPECT_TRUE(solver.touched_nodes().empty());
}

// A 1000-step random walk of the sphere in and out of the block: every step converges or
// records why (and then keeps its state); every converged state meets the contact conditions,
// so no touched set is left oscillating unreported.
TEST(ContactProbe, RandomPathConvergesOrRecordsTheReason) {
  Problem p = block_problem(6);
  p.solver.substeps = 1;
  p.solver.tolerance = 1e-9;
  const Independent truth(p);
  PathSolver solver(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.06, 0.06);
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int failures = 0, touching = 0, changes = 0;
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3d next = t + Eigen::Vector3d(step(rng), step(rng), step(rng) - 0.004);
    // Keep the centre over the block, between 0.2 clear and 0.45 deep.
    next.x() = std::clamp(next.x(), -1.0, 1.0);
    next.y() = std::clamp(next.y(), -1.0, 1.0);
    next.z() = std::clamp(next.z(), -0.95, -0.3);
    const Eigen::VectorXd before = solver.state_m();
    const MoveResult r = solver.move_to(next);
    if (!r.ok) {
      ++failures;
      std::printf("step %d: %s: %s\n", i, failure_name(r.failure), r.reason.c_str());
      EXPECT_FALSE(r.reason.empty()) << "step " << i;
      EXPECT_NE(r.failure, SolveFailure::kNone) << "step " << i;
      EXPECT_EQ(solver.state_m(), before) << "step " << i;
      continue;
    }
    t = next;
    changes += r.active_set_iterations;
    if (!solver.touched_nodes().empty()) ++touching;
    const ContactCheck c = truth.check(solver);
    expect_contact_conditions(c, 0.8, "step " + std::to_string(i));
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_LE(failures, 10);
  EXPECT_GT(touching, 500);  // the walk really is in contact most of the time
  EXPECT_GT(changes, 100);   // and the touched set really changes along it
  std::printf("random path: %d failures, %d steps touching, %d active-set changes\n", failures,
              touching, changes);
}

}  // namespace
}  // namespace hapstate
