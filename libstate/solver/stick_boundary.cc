// Sticking contact (docs/contact.md): the nodes the sphere touches follow it rigidly, each at
// its anchor; the set is decided by the active-set loop of settle() over solver/contact_set.h.
#include "solver/contact_set.h"
#include "solver/move_result.h"
#include "solver/probe_boundary.h"

#include <algorithm>
#include <string>

namespace hapstate {
namespace {

class StickBoundary final : public ProbeBoundary {
 public:
  explicit StickBoundary(const Problem& problem)
      : set_(problem.mesh.nodes, *problem.contact, problem.probe_rest),
        rest_(problem.probe_rest),
        unit_(problem.unit) {}

  void reset() override { set_.clear(); }
  void set_state(const Eigen::VectorXd& u_m, const Eigen::Vector3d& t,
                 const std::vector<int>& touched, const std::vector<double>&) override {
    set_.assign(touched, u_m, unit_, rest_ + t);
  }
  BoundaryState save() const override {
    BoundaryState s;
    s.touched = set_.touched();
    s.anchors = set_.anchors();
    return s;
  }
  void restore(const BoundaryState& s) override { set_.restore({s.touched, s.anchors}); }
  std::vector<int> touched_nodes(const Eigen::VectorXd&, const Eigen::Vector3d&) const override {
    return set_.touched();
  }
  const ContactTimings* timings() const override { return &set_.timings(); }

  // The touched nodes' DOFs follow the centre: u = base + t, base = centre_rest + anchor - X.
  void prescribe(Prescription* p) const override {
    const std::vector<int>& touched = set_.touched();
    for (std::size_t k = 0; k < touched.size(); ++k) {
      const Eigen::Vector3d base = set_.prescribed(static_cast<int>(k), rest_);
      for (int c = 0; c < 3; ++c) {
        const int d = 3 * touched[k] + c;
        p->role[d] = DofRole::kProbe;
        p->component[d] = c;
        p->base[d] = base[c] * unit_;
      }
    }
  }

  bool allows_inexact_newton() const override { return false; }
  // The release decisions read the reactions: they must be converged at every sub-step.
  bool converges_every_substep() const override { return true; }
  bool keeps_newton_force() const override { return false; }

  // Nothing touched and the body at rest: only collision detection is needed.
  bool settled_without_solve(SettleHost& host, const Eigen::Vector3d& t_to,
                             const SolverOptions& options, MoveResult* result, bool* ok) override {
    if (!set_.touched().empty() || !host.state().isZero(0.0)) return false;
    *ok = settle(host, t_to, options.tolerance, true, options, result);
    return true;
  }

  bool settle(SettleHost& host, const Eigen::Vector3d& t, double rel_tol, bool last,
              const SolverOptions& options, MoveResult* result) override;

 private:
  ContactSet set_;
  Eigen::Vector3d rest_;
  double unit_;
};

// The active-set loop at probe displacement t, from an equilibrium (the host's force at its
// state): release adhesive touched nodes, add penetrating ones, re-solve, until the set is
// stable.
bool StickBoundary::settle(SettleHost& host, const Eigen::Vector3d& t, double rel_tol, bool,
                           const SolverOptions& options, MoveResult* result) {
  const Eigen::Vector3d centre = rest_ + t;
  // A set repeats when the same nodes come back with the same anchors: a node released and
  // re-added from where it sprang back gets a new anchor (it slides along the sphere) and is
  // progress, not a cycle.
  const double same_anchor = 1e-9 * set_.radius();
  auto same = [&](const ContactSet::Held& a, const ContactSet::Held& b) {
    if (a.nodes != b.nodes) return false;
    for (std::size_t k = 0; k < a.anchors.size(); ++k)
      if ((a.anchors[k] - b.anchors[k]).norm() > same_anchor) return false;
    return true;
  };
  std::vector<ContactSet::Held> seen{set_.held()};
  for (int it = 0;; ++it) {
    const ContactChange change =
        set_.decide(host.state(), unit_, host.force(), centre, options.absolute_tolerance);
    if (change.empty()) return true;
    if (it >= options.max_active_set_iterations) {
      result->failure = SolveFailure::kContactUnsettled;
      result->reason = "the touched set still changed after " +
                       std::to_string(options.max_active_set_iterations) +
                       " active-set iterations (" + std::to_string(change.added.size()) +
                       " node(s) to add, " + std::to_string(change.released.size()) +
                       " to release)";
      return false;
    }
    set_.apply(change, host.state(), unit_, centre);
    ++result->active_set_iterations;
    const ContactSet::Held now = set_.held();
    if (std::any_of(seen.begin(), seen.end(),
                    [&](const ContactSet::Held& h) { return same(h, now); })) {
      std::string nodes;
      for (int n : change.added) nodes += " +" + std::to_string(n);
      for (int n : change.released) nodes += " -" + std::to_string(n);
      result->failure = SolveFailure::kContactCycle;
      result->reason = "the touched set oscillates: after" + nodes +
                       " it is a set (nodes and anchors) it already had in this sub-step";
      return false;
    }
    seen.push_back(now);
    host.prescription_changed(t);
    if (set_.touched().empty()) {
      // Nothing loads the body: it is at rest (exactly).
      host.state().setZero();
      continue;
    }
    if (!host.newton(rel_tol, result, false)) return false;
  }
}

}  // namespace

std::unique_ptr<ProbeBoundary> make_stick_boundary(const Problem& problem) {
  return std::make_unique<StickBoundary>(problem);
}

}  // namespace hapstate
