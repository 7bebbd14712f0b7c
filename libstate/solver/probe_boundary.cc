#include "solver/probe_boundary.h"

namespace hapstate {
namespace {

// A grabbed node or patch: its DOFs follow the probe, u = t; nothing else.
class GrabBoundary final : public ProbeBoundary {
 public:
  explicit GrabBoundary(const Problem& problem) : probe_nodes_(problem.constraints.probe_nodes) {}

  void prescribe(Prescription* p) const override {
    for (int n : probe_nodes_)
      for (int c = 0; c < 3; ++c)
        if (p->role[3 * n + c] == DofRole::kProbe) p->component[3 * n + c] = c;
  }

 private:
  std::vector<int> probe_nodes_;
};

}  // namespace

std::unique_ptr<ProbeBoundary> make_probe_boundary(const Problem& problem,
                                                   const Assembler& assembler,
                                                   const std::vector<DofRole>& role) {
  if (!problem.contact) return std::make_unique<GrabBoundary>(problem);
  if (problem.contact->friction == Friction::kStick) return make_stick_boundary(problem);
  return make_sliding_boundary(problem, assembler, role);
}

}  // namespace hapstate
