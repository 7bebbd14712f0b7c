// Per-Newton-iteration costs of the precise solver on the bundled meshes: assembly of energy,
// force and tangent; numeric Cholesky factorisation (CHOLMOD simplicial vs supernodal, one
// symbolic analysis); triangular solves. Run: build/bench/solver_bench (see docs/benchmarks.md).
#include "fem/assembler.h"
#include "mesh/load.h"
#include "solver/sparse_cholesky.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

namespace hapstate {
namespace {

const char* const kMeshes[] = {"liver.msh", "liverCoarse.vtu", "liverSemiFine.vtu", "liverFine.vtu",
                               "bunny.msh"};

// One mesh with a neo-Hooke material, a deformed state and its constrained tangent.
struct Setup {
  Mesh mesh;
  std::unique_ptr<Material> material;
  std::unique_ptr<Assembler> assembler;
  Eigen::VectorXd u, f;
  std::vector<double> k;
};

Setup& setup(int index) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[index];
  if (!s) {
    s = std::make_unique<Setup>();
    s->mesh = load_mesh(std::string(HAPSTATE_DATA_DIR) + "/meshes/" + kMeshes[index]);
    s->material = make_material(constants_from_young_poisson(Law::kNeoHooke, 5000, 0.45));
    const Eigen::Matrix3Xd x = s->mesh.nodes * 0.01;
    s->assembler = std::make_unique<Assembler>(x, s->mesh.tets, *s->material);
    // A smooth 2 % shear so the tangent is not the rest one.
    s->u.setZero(3 * s->mesh.num_nodes());
    for (int n = 0; n < s->mesh.num_nodes(); ++n) s->u[3 * n] = 0.02 * x(1, n);
    s->assembler->energy_force_tangent(s->u, &s->f, &s->k);
    // Hold the 5 % of nodes with the smallest x (removes rigid modes): identity rows.
    const SymmetricPattern& p = s->assembler->pattern();
    const double cut = x.row(0).minCoeff() + 0.05 * (x.row(0).maxCoeff() - x.row(0).minCoeff());
    for (int col = 0; col < p.n; ++col)
      for (int e = p.col_ptr[col]; e < p.col_ptr[col + 1]; ++e) {
        const int row = p.row_idx[e];
        if (x(0, row / 3) < cut || x(0, col / 3) < cut) s->k[e] = row == col ? 1.0 : 0.0;
      }
  }
  return *s;
}

void label(benchmark::State& state, const Setup& s) {
  state.SetLabel(std::string(kMeshes[state.range(0)]) + " " +
                 std::to_string(3 * s.mesh.num_nodes()) + " DOFs");
}

void BM_Assembly(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  Eigen::VectorXd f;
  std::vector<double> k;
  for (auto _ : state) benchmark::DoNotOptimize(s.assembler->energy_force_tangent(s.u, &f, &k));
  label(state, s);
}

void BM_SymbolicAnalysis(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  for (auto _ : state) SparseCholesky chol(s.assembler->pattern());
  label(state, s);
}

void factorize(benchmark::State& state, SparseCholesky::Method method) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  SparseCholesky chol(s.assembler->pattern(), method);
  for (auto _ : state)
    if (!chol.factorize(s.k)) state.SkipWithError("not positive definite");
  label(state, s);
}
void BM_FactorizeSimplicial(benchmark::State& state) {
  factorize(state, SparseCholesky::Method::kSimplicial);
}
void BM_FactorizeSupernodal(benchmark::State& state) {
  factorize(state, SparseCholesky::Method::kSupernodal);
}

void BM_Solve(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  SparseCholesky chol(s.assembler->pattern());
  chol.factorize(s.k);
  Eigen::VectorXd x;
  for (auto _ : state) chol.solve(s.f, &x);
  label(state, s);
}

BENCHMARK(BM_Assembly)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SymbolicAnalysis)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeSimplicial)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeSupernodal)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Solve)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hapstate

BENCHMARK_MAIN();
