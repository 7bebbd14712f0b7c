// Downstream use of an installed hapstate: a cantilever box, neo-Hooke, one probe move.
// Prints the felt force; exits 0 only if the solve converged to the expected equilibrium.
#include <mesh/box_mesh.h>  // installed under include/hapstate, the include dir of hapstate::state
#include <solver/path_solver.h>

#include <cmath>
#include <cstdio>

int main() {
  using namespace hapstate;
  Problem p;
  p.mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(4, 1, 1), 4, 1, 1);
  p.unit = 0.01;
  p.material = constants_from_young_poisson(Law::kNeoHooke, 1e5, 0.3);
  p.constraints.role.assign(3 * p.mesh.num_nodes(), DofRole::kFree);
  for (int n : p.mesh.groups.at("xmin"))
    for (int c = 0; c < 3; ++c) p.constraints.role[3 * n + c] = DofRole::kFixed;
  int tip = -1;
  for (int n = 0; n < p.mesh.num_nodes(); ++n)
    if ((p.mesh.nodes.col(n) - Eigen::Vector3d(4, 1, 1)).norm() < 1e-12) tip = n;
  if (tip < 0) { std::fprintf(stderr, "consumer: no tip node\n"); return 1; }
  p.constraints.probe_nodes = {tip};
  for (int c = 0; c < 3; ++c) p.constraints.role[3 * tip + c] = DofRole::kProbe;
  p.probe_rest = p.mesh.nodes.col(tip);

  PathSolver solver(p);
  const MoveResult r = solver.move_to(Eigen::Vector3d(0, 0, 0.5));
  if (!r.ok) {
    std::fprintf(stderr, "consumer: move failed: %s: %s\n", failure_name(r.failure), r.reason.c_str());
    return 1;
  }
  const Eigen::Vector3d f = solver.force_felt();
  std::printf("consumer: %d nodes, %d iterations, force felt = %.9g %.9g %.9g N\n",
              p.mesh.num_nodes(), r.iterations, f.x(), f.y(), f.z());
  // Lifting the tip: the beam pulls the hand back down.
  return f.allFinite() && f.z() < 0 ? 0 : 1;
}
