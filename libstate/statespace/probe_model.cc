#include "statespace/probe_model.h"

#include "util/error.h"

namespace hapstate {
namespace {

class GrabProbe final : public ProbeModel {
 public:
  explicit GrabProbe(const Problem& problem) : problem_(problem) {
    const auto& role = problem.constraints.role;
    for (int d = 0; d < static_cast<int>(role.size()); ++d)
      if (role[d] == DofRole::kProbe) dofs_.push_back(d);
  }

  Eigen::Vector3d rest_position() const override { return problem_.probe_rest; }

  ProbeLoad load_at(const Eigen::Vector3d& p) const override {
    const Eigen::Vector3d t = p - problem_.probe_rest;
    ProbeLoad load;
    load.dofs = dofs_;
    for (int d : dofs_) load.values.push_back(t[d % 3]);
    return load;
  }

  void set_state(PathSolver& solver, const std::vector<double>& u,
                 const Eigen::Vector3d& p) const override {
    Eigen::VectorXd u_m = Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
    u_m *= problem_.unit;
    solver.set_state(u_m, p - problem_.probe_rest);
  }

  MoveResult move_to(PathSolver& solver, const Eigen::Vector3d& p) const override {
    return solver.move_to(p - problem_.probe_rest);
  }

  bool holds_zero_configuration(const Eigen::Vector3d& p) const override {
    return p == problem_.probe_rest;
  }

 private:
  const Problem& problem_;
  std::vector<int> dofs_;
};

}  // namespace

std::unique_ptr<ProbeModel> make_probe_model(const Problem& problem, ProbeMode mode) {
  if (mode != ProbeMode::kGrab) {
    throw InputError("probe.mode = \"contact\": the state space supports only grab probes yet");
  }
  return std::make_unique<GrabProbe>(problem);
}

}  // namespace hapstate
