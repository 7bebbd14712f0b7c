// Assembly against finite differences of the total energy, and the patch test.
#include "fem/assembler.h"
#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <random>

namespace hapstate {
namespace {

struct Case {
  const char* name;
  MaterialConstants constants;
};

std::vector<Case> cases() {
  return {{"linear", constants_from_young_poisson(Law::kLinear, 5000, 0.3)},
          {"stvk", constants_from_young_poisson(Law::kStvk, 5000, 0.45)},
          {"neohooke", constants_from_young_poisson(Law::kNeoHooke, 5000, 0.45)},
          {"mooney", constants_from_young_poisson(Law::kMooney, 5000, 0.45)}};
}

// A 2x2x2-cell box (metres) with a smooth random displacement of ~10% strain.
struct Fixture {
  Mesh mesh = make_box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.02, 0.03, 0.025), 2, 2, 2);
  Eigen::VectorXd random_u(unsigned seed, double scale) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-1, 1);
    Eigen::VectorXd u(3 * mesh.num_nodes());
    for (int i = 0; i < u.size(); ++i) u[i] = scale * d(rng);
    return u;
  }
};

TEST(Assembler, ForceIsCentralDifferenceOfEnergy) {
  Fixture fx;
  for (const Case& c : cases()) {
    auto material = make_material(c.constants);
    Assembler assembler(fx.mesh.nodes, fx.mesh.tets, *material);
    for (unsigned seed : {1u, 2u, 3u}) {
      const Eigen::VectorXd u = fx.random_u(seed, 1e-3);
      Eigen::VectorXd f;
      assembler.energy_and_force(u, &f);
      ASSERT_GT(f.norm(), 1e-3) << c.name;  // not trivially zero
      const double h = 1e-7;
      Eigen::VectorXd fd(u.size());
      for (int i = 0; i < u.size(); ++i) {
        Eigen::VectorXd up = u, um = u;
        up[i] += h;
        um[i] -= h;
        fd[i] = (assembler.energy(up) - assembler.energy(um)) / (2 * h);
      }
      EXPECT_LE((fd - f).norm(), 1e-6 * f.norm()) << c.name << " seed " << seed;
    }
  }
}

TEST(Assembler, TangentIsCentralDifferenceOfForce) {
  Fixture fx;
  for (const Case& c : cases()) {
    auto material = make_material(c.constants);
    Assembler assembler(fx.mesh.nodes, fx.mesh.tets, *material);
    const Eigen::VectorXd u = fx.random_u(7, 1e-3);
    Eigen::VectorXd f;
    std::vector<double> k;
    assembler.energy_force_tangent(u, &f, &k);
    for (unsigned seed : {11u, 12u}) {
      const Eigen::VectorXd v = fx.random_u(seed, 1.0);
      Eigen::VectorXd kv;
      symmetric_multiply(assembler.pattern(), k, v, &kv);
      const double h = 1e-8;
      Eigen::VectorXd fp, fm;
      assembler.energy_and_force(u + h * v, &fp);
      assembler.energy_and_force(u - h * v, &fm);
      const Eigen::VectorXd fd = (fp - fm) / (2 * h);
      ASSERT_GT(kv.norm(), 1.0) << c.name;
      EXPECT_LE((fd - kv).norm(), 1e-6 * kv.norm()) << c.name << " seed " << seed;
    }
  }
}

// Gravity and supports (fem/loads.h) enter energy, force and tangent consistently: the force is
// the energy's central difference and the tangent the force's, with a body force and springs on
// some DOFs; the load scale multiplies the body force alone; gravity_force lumps m g exactly.
TEST(Assembler, BodyLoadsAreConsistentWithTheEnergy) {
  Fixture fx;
  BodyLoads loads;
  loads.force = gravity_force(fx.mesh.nodes, fx.mesh.tets, 1000.0, Eigen::Vector3d(0.3, 0, -9.81));
  const double volume = 0.02 * 0.03 * 0.025;
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();
  for (int n = 0; n < fx.mesh.num_nodes(); ++n) weight += loads.force.segment<3>(3 * n);
  EXPECT_NEAR((weight - 1000.0 * volume * Eigen::Vector3d(0.3, 0, -9.81)).norm(), 0.0, 1e-12);
  std::vector<bool> bottom(fx.mesh.num_nodes(), false);
  for (int n = 0; n < fx.mesh.num_nodes(); ++n) bottom[n] = fx.mesh.nodes(2, n) == 0.0;
  ASSERT_EQ(add_surface_springs(fx.mesh.nodes, fx.mesh.surface, bottom, 2e5, {true, false, true},
                                &loads.spring),
            2 * 2 * 2);                                          // 2 x 2 cells of 2 triangles
  EXPECT_NEAR(loads.spring.sum(), 2 * 2e5 * 0.02 * 0.03, 1e-9);  // x and z over the face
  for (const Case& c : cases()) {
    auto material = make_material(c.constants);
    Assembler plain(fx.mesh.nodes, fx.mesh.tets, *material);
    Assembler assembler(fx.mesh.nodes, fx.mesh.tets, *material);
    assembler.set_loads(&loads);
    assembler.set_load_scale(0.7);
    const Eigen::VectorXd u = fx.random_u(5, 1e-3);
    Eigen::VectorXd f, f0;
    std::vector<double> k, k0;
    const double w = assembler.energy_force_tangent(u, &f, &k);
    const double w0 = plain.energy_force_tangent(u, &f0, &k0);
    double springs = 0;
    for (int d = 0; d < u.size(); ++d) springs += 0.5 * loads.spring[d] * u[d] * u[d];
    EXPECT_NEAR(w, w0 - 0.7 * loads.force.dot(u) + springs, 1e-12 * std::abs(w0)) << c.name;
    EXPECT_LE((f - (f0 - 0.7 * loads.force + loads.spring.cwiseProduct(u))).norm(),
              1e-12 * f.norm())
        << c.name;
    const double h = 1e-7;
    Eigen::VectorXd fd(u.size());
    for (int i = 0; i < u.size(); ++i) {
      Eigen::VectorXd up = u, um = u;
      up[i] += h;
      um[i] -= h;
      fd[i] = (assembler.energy(up) - assembler.energy(um)) / (2 * h);
    }
    EXPECT_LE((fd - f).norm(), 1e-6 * f.norm()) << c.name;
    const Eigen::VectorXd v = fx.random_u(13, 1.0);
    Eigen::VectorXd kv, fp, fm;
    symmetric_multiply(assembler.pattern(), k, v, &kv);
    assembler.energy_and_force(u + 1e-8 * v, &fp);
    assembler.energy_and_force(u - 1e-8 * v, &fm);
    EXPECT_LE(((fp - fm) / 2e-8 - kv).norm(), 1e-6 * kv.norm()) << c.name;
    EXPECT_NEAR(assembler.load_norm(), 0.7 * loads.force.norm(), 1e-15);
  }
}

// Patch test: a homogeneous deformation u = G X + b leaves every interior node in equilibrium
// (zero internal force) and its force on the boundary equals the traction P N of the closed form.
// Threads compute the element terms; the scatter keeps the serial order, so the energy, force
// and tangent are bitwise those of one thread (also with the PSD projection, and an inverted
// element still gives an infinite energy).
TEST(Assembler, ThreadsGiveBitwiseTheSameAssembly) {
  Fixture fx;
  for (const Case& c : cases()) {
    auto material = make_material(c.constants);
    Assembler serial(fx.mesh.nodes, fx.mesh.tets, *material);
    Assembler threaded(fx.mesh.nodes, fx.mesh.tets, *material);
    threaded.set_threads(3);
    const Eigen::VectorXd u = fx.random_u(7, 1e-3);
    for (bool psd : {false, true}) {
      Eigen::VectorXd f1, f2;
      std::vector<double> k1, k2;
      const double w1 = serial.energy_force_tangent(u, &f1, &k1, psd);
      const double w2 = threaded.energy_force_tangent(u, &f2, &k2, psd);
      EXPECT_EQ(w1, w2) << c.name;
      EXPECT_TRUE((f1.array() == f2.array()).all()) << c.name;
      EXPECT_EQ(k1, k2) << c.name;
    }
    if (c.constants.law == Law::kLinear || c.constants.law == Law::kStvk) continue;  // any J
    Eigen::VectorXd inverted = Eigen::VectorXd::Zero(u.size());
    inverted[0] = 1.0;  // moves a corner node 1 m through the box
    Eigen::VectorXd f;
    std::vector<double> k;
    EXPECT_FALSE(std::isfinite(threaded.energy_force_tangent(inverted, &f, &k))) << c.name;
  }
}

TEST(Assembler, PatchTestLinearFieldIsExactEquilibrium) {
  // 3x3x3 cells: 64 nodes, 8 of them interior.
  const Mesh mesh =
      make_box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.02, 0.03, 0.025), 3, 3, 3);
  Eigen::Matrix3d g;
  g << 0.10, 0.02, -0.03, 0.01, -0.05, 0.04, 0.02, 0.03, 0.07;
  const Eigen::Vector3d b(0.001, -0.002, 0.0005);
  Eigen::VectorXd u(3 * mesh.num_nodes());
  for (int n = 0; n < mesh.num_nodes(); ++n) u.segment<3>(3 * n) = g * mesh.nodes.col(n) + b;
  std::vector<bool> boundary(mesh.num_nodes(), false);
  for (int t = 0; t < mesh.surface.cols(); ++t)
    for (int a = 0; a < 3; ++a) boundary[mesh.surface(a, t)] = true;
  for (const Case& c : cases()) {
    auto material = make_material(c.constants);
    Assembler assembler(mesh.nodes, mesh.tets, *material);
    Eigen::VectorXd f;
    assembler.energy_and_force(u, &f);
    Mat3 p;
    material->evaluate(Mat3::Identity() + g, &p, nullptr);
    const double scale = p.norm() * 0.01 * 0.01;  // stress x a cell face area [N]
    ASSERT_GT(scale, 1e-3) << c.name;
    int interior = 0;
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (boundary[n]) continue;
      ++interior;
      EXPECT_LE(f.segment<3>(3 * n).norm(), 1e-10 * scale) << c.name << " node " << n;
    }
    EXPECT_EQ(interior, 8);
    // Whole-body balance: internal forces sum to zero.
    const Eigen::Map<const Eigen::Matrix3Xd> f_nodes(f.data(), 3, mesh.num_nodes());
    EXPECT_LE(f_nodes.rowwise().sum().norm(), 1e-10 * scale) << c.name;
  }
}

}  // namespace
}  // namespace hapstate
