// The CalculiX export checked against closed forms, independently of our solver: a cube with
// symmetry-plane supports stretched and compressed in x, laterally free. The homogeneous state
// F = diag(a, b, b) is exact on any tet mesh, so ccx's reaction must match P11(a, b) * area with
// b solving P22(a, b) = 0, and its displacements must be the affine field.
#include "ccx/deck.h"
#include "ccx/read_dat.h"
#include "ccx/run.h"
#include "mesh/box_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace hapstate {
namespace {

constexpr double kYoung = 5e4;  // Pa, soft tissue
constexpr double kPoisson = 0.3;
constexpr double kUnit = 0.01;  // 1 mesh unit = 1 cm: the unit cube gives forces of ~1 N
constexpr double kRtol = 1e-4;

MaterialConstants constants(Law law) {
  MaterialConstants c;
  c.law = law;
  c.mu = kYoung / (2 * (1 + kPoisson));
  c.lambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
  const double bulk = kYoung / (3 * (1 - 2 * kPoisson));
  c.d1 = 2 / bulk;
  c.c10 = law == Law::kMooney ? 0.8 * c.mu / 2 : c.mu / 2;
  c.c01 = law == Law::kMooney ? 0.2 * c.mu / 2 : 0;
  return c;
}

// Principal second Piola-Kirchhoff stress S_i for principal stretches (l1, l2, l3), i = 0..2.
double principal_pk2(const MaterialConstants& c, const Eigen::Vector3d& l, int i) {
  const Eigen::Vector3d l2 = l.cwiseProduct(l);
  switch (c.law) {
    case Law::kLinear: {
      const Eigen::Vector3d eps = l.array() - 1;
      return c.lambda * eps.sum() + 2 * c.mu * eps[i];  // Cauchy = PK1 = PK2 when linear
    }
    case Law::kStvk: {
      const Eigen::Vector3d e = (l2.array() - 1) / 2;
      return c.lambda * e.sum() + 2 * c.mu * e[i];
    }
    case Law::kNeoHooke:
    case Law::kMooney: {
      const double j = l.prod();
      const double i1 = l2.sum();
      const double i2 = l2[0] * l2[1] + l2[1] * l2[2] + l2[0] * l2[2];
      return 2 * c.c10 * std::pow(j, -2.0 / 3) * (1 - i1 / (3 * l2[i])) +
             2 * c.c01 * std::pow(j, -4.0 / 3) * (i1 - l2[i] - 2 * i2 / (3 * l2[i])) +
             2 / c.d1 * (j - 1) * j / l2[i];
    }
  }
  return 0;
}

// Uniaxial stress with stretch a in x: lateral stretch b from S22 = 0 (scalar Newton with a
// central-difference slope), and P11 = a S11 (S11 itself for the linear law).
struct Uniaxial {
  double lateral, p11;
};

Uniaxial uniaxial(const MaterialConstants& c, double a) {
  auto s22 = [&](double b) { return principal_pk2(c, {a, b, b}, 1); };
  double b = 1;
  for (int it = 0; it < 100; ++it) {
    const double h = 1e-7;
    const double slope = (s22(b + h) - s22(b - h)) / (2 * h);
    const double db = -s22(b) / slope;
    b += db;
    if (std::abs(db) < 1e-15) break;
  }
  EXPECT_LT(std::abs(s22(b)), 1e-9 * c.mu);
  const double s11 = principal_pk2(c, {a, b, b}, 0);
  return {b, c.law == Law::kLinear ? s11 : a * s11};
}

// Unit cube, 2x2x2 cells: x fixed on x=0, y on y=0, z on z=0; the x=1 face is the probe, x only.
Problem cube_problem(Law law) {
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 1), 2, 2, 2);
  p.unit = kUnit;
  p.material = constants(law);
  const int n = p.mesh.num_nodes();
  p.constraints.role.assign(3 * n, DofRole::kFree);
  p.constraints.probe_components = {true, false, false};
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = p.mesh.nodes.col(i);
    for (int c = 0; c < 3; ++c) {
      if (x[c] == 0) p.constraints.role[3 * i + c] = DofRole::kFixed;
    }
    if (x.x() == 1) {
      p.constraints.role[3 * i] = DofRole::kProbe;
      p.constraints.probe_nodes.push_back(i);
    }
  }
  p.probe_rest = {1, 0.5, 0.5};
  return p;
}

class CcxUniaxial : public ::testing::TestWithParam<Law> {};

TEST_P(CcxUniaxial, MatchesClosedForm) {
  const Law law = GetParam();
  const Problem problem = cube_problem(law);
  const std::vector<double> stretches{1.1, 1.2, 1.0, 0.9, 0.8};
  std::vector<Eigen::Vector3d> path;
  for (double a : stretches) path.emplace_back(a, 0.5, 0.5);

  const std::filesystem::path dir = std::filesystem::path(HAPSTATE_BINARY_DIR) / "tests" /
                                    "ccx_out" / ("uniaxial_" + std::string(law_name(law)));
  std::filesystem::remove_all(dir);
  write_ccx_deck(problem, path, dir);
  run_ccx(dir);  // fails (not skips) when ccx is missing
  const auto results = ccx_path_results(
      problem, read_ccx_dat(dir / (std::string(kCcxJobName) + ".dat")), path.size());
  ASSERT_EQ(results.size(), path.size());

  const double area = kUnit * kUnit;
  double max_force = 0;
  for (double a : stretches)
    max_force = std::max(max_force, std::abs(uniaxial(problem.material, a).p11 * area));
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double a = stretches[k];
    const Uniaxial exact = uniaxial(problem.material, a);
    // The user pulls the face in +x and feels the body pull back: felt = -P11 * area.
    const double felt_exact = -exact.p11 * area;
    const Eigen::Vector3d felt = results[k].force_felt;
    const double scale = a == 1.0 ? max_force : std::abs(felt_exact);
    SCOPED_TRACE("law " + std::string(law_name(law)) + ", stretch " + std::to_string(a));
    std::printf("  %-8s stretch %.2f: ccx felt fx = %+.7e N, closed form %+.7e N, rel %.2e\n",
                std::string(law_name(law)).c_str(), a, felt.x(), felt_exact,
                std::abs(felt.x() - felt_exact) / scale);
    EXPECT_LE(std::abs(felt.x() - felt_exact), kRtol * scale);
    EXPECT_EQ(felt.y(), 0);  // y, z do not follow the probe
    EXPECT_EQ(felt.z(), 0);

    double u_err = 0, u_max = 0;
    for (int i = 0; i < problem.mesh.num_nodes(); ++i) {
      const Eigen::Vector3d x = problem.mesh.nodes.col(i);
      const Eigen::Vector3d u_exact((a - 1) * x.x(), (exact.lateral - 1) * x.y(),
                                    (exact.lateral - 1) * x.z());
      u_err = std::max(u_err, (results[k].displacement.col(i) - u_exact).cwiseAbs().maxCoeff());
      u_max = std::max(u_max, u_exact.cwiseAbs().maxCoeff());
    }
    EXPECT_LE(u_err, kRtol * std::max(u_max, 0.2)) << "displacement error " << u_err;
  }
}

INSTANTIATE_TEST_SUITE_P(Laws, CcxUniaxial,
                         ::testing::Values(Law::kLinear, Law::kStvk, Law::kNeoHooke, Law::kMooney),
                         [](const auto& info) { return std::string(law_name(info.param)); });

}  // namespace
}  // namespace hapstate
