// hapstate::SceneSolver (include/hapstate/solver.h): the precise path solver on a scene file,
// for programs that link the installed library. A thin owner of the Problem and its PathSolver.
#include "hapstate/solver.h"

#include "problem/problem.h"
#include "scene/bind.h"
#include "scene/scene.h"
#include "solver/path_solver.h"

namespace hapstate {

struct SceneSolver::Impl {
  explicit Impl(Problem p) : problem(std::move(p)), solver(problem) {}
  Problem problem;  // PathSolver keeps a reference to parts of it: declared first
  PathSolver solver;
};

SceneSolver::SceneSolver(const std::string& scene_file)
    : impl_(std::make_unique<Impl>(build_problem(load_scene(scene_file)))) {}

SceneSolver::~SceneSolver() = default;
SceneSolver::SceneSolver(SceneSolver&&) noexcept = default;
SceneSolver& SceneSolver::operator=(SceneSolver&&) noexcept = default;

int SceneSolver::num_nodes() const { return impl_->problem.mesh.num_nodes(); }
double SceneSolver::unit() const { return impl_->problem.unit; }
Eigen::Vector3d SceneSolver::probe_rest() const { return impl_->problem.probe_rest; }
bool SceneSolver::contact() const { return impl_->problem.contact.has_value(); }

MoveOutcome SceneSolver::move_to(const Eigen::Vector3d& probe_position) {
  const MoveResult r = impl_->solver.move_to(probe_position - impl_->problem.probe_rest);
  MoveOutcome out;
  out.ok = r.ok;
  out.failure = r.ok ? "" : failure_name(r.failure);
  out.reason = r.reason;
  out.iterations = r.iterations;
  out.substeps = r.substeps;
  out.cutbacks = r.cutbacks;
  out.residual = r.residual;
  out.wall_ms = r.wall_ms;
  return out;
}

void SceneSolver::reset() { impl_->solver.reset(); }
Eigen::Vector3d SceneSolver::force_felt() const { return impl_->solver.force_felt(); }
Eigen::Matrix3d SceneSolver::haptic_stiffness() { return impl_->solver.haptic_stiffness(); }
Eigen::Matrix3Xd SceneSolver::displacements() const { return impl_->solver.displacements(); }

}  // namespace hapstate
