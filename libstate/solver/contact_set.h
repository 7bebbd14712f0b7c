// The contact probe's active set (docs/contact.md): which surface nodes the rigid sphere holds,
// and where. Sticking model: a node that comes to penetrate the sphere is put back on the
// sphere's surface along the ray from the centre, and from then on moves rigidly with the
// sphere (its anchor, the offset from the centre, is fixed while it is touched). A touched node
// whose reaction pulls the sphere (adhesion) is released. The PathSolver runs the loop; this
// class holds the set and makes the geometric and force decisions.
#pragma once

#include "problem/problem.h"
#include "solver/contact_timings.h"

#include <Eigen/Core>

#include <vector>

namespace hapstate {

// Tolerances of the active-set decisions.
// A node is added when it is deeper than kPenetrationTolerance x radius inside the sphere.
inline constexpr double kPenetrationTolerance = 1e-4;
// A touched node is released when its reaction pulls the sphere by more than
// kAdhesionTolerance x the largest touched-node reaction (and more than the solver's absolute
// tolerance).
inline constexpr double kAdhesionTolerance = 1e-3;

struct ContactChange {
  std::vector<int> released;  // adhesive touched nodes, ascending
  std::vector<int> added;     // penetrating free nodes, ascending
  bool empty() const { return released.empty() && added.empty(); }
};

class ContactSet {
 public:
  // `reference`: node positions (mesh units); `centre_rest`: the sphere centre at rest.
  ContactSet(const Eigen::Matrix3Xd& reference, const ContactSphere& sphere,
             const Eigen::Vector3d& centre_rest);

  double radius() const { return radius_; }
  const std::vector<int>& touched() const { return touched_; }
  // anchors()[k]: offset of touched()[k] from the centre (mesh units, length radius).
  const std::vector<Eigen::Vector3d>& anchors() const { return anchors_; }
  // Prescribed displacement (mesh units) of touched()[k] with the sphere centre at `centre`.
  Eigen::Vector3d prescribed(int k, const Eigen::Vector3d& centre) const;

  // Candidate nodes strictly inside the sphere by more than the penetration tolerance, on the
  // deformed surface x = X + u_m / unit (u_m in metres, 3 per node), ascending. A scan: see
  // penetrating() in contact_set.cc for why no index.
  std::vector<int> penetrating(const Eigen::VectorXd& u_m, double unit,
                               const Eigen::Vector3d& centre);
  // The active-set decision at an equilibrium: `f` is the internal force (N, 3 per node) at u_m;
  // touched nodes with an adhesive reaction are released, untouched penetrating nodes added.
  ContactChange decide(const Eigen::VectorXd& u_m, double unit, const Eigen::VectorXd& f,
                       const Eigen::Vector3d& centre, double absolute_tolerance);
  // Applies a decision: released nodes leave; added nodes get the anchor of their radial
  // projection onto the sphere (from the deformed position).
  void apply(const ContactChange& change, const Eigen::VectorXd& u_m, double unit,
             const Eigen::Vector3d& centre);
  // Sets the touched nodes of a stored state: anchors from the deformed positions,
  // normalised to the radius. Throws InputError for a node that is not a candidate.
  void assign(const std::vector<int>& nodes, const Eigen::VectorXd& u_m, double unit,
              const Eigen::Vector3d& centre);
  void clear() {
    touched_.clear();
    anchors_.clear();
  }
  // Save and restore the touched nodes with their anchors (the solver's cut-back).
  struct Held {
    std::vector<int> nodes;
    std::vector<Eigen::Vector3d> anchors;
  };
  Held held() const { return {touched_, anchors_}; }
  void restore(const Held& h) {
    touched_ = h.nodes;
    anchors_ = h.anchors;
  }

  const ContactTimings& timings() const { return timings_; }

 private:
  Eigen::Vector3d anchor_of(int node, const Eigen::VectorXd& u_m, double unit,
                            const Eigen::Vector3d& centre) const;

  Eigen::Matrix3Xd reference_;
  double radius_;
  std::vector<int> candidates_;
  std::vector<char> is_candidate_;
  Eigen::Vector3d centre_rest_;
  std::vector<int> touched_;
  std::vector<Eigen::Vector3d> anchors_;
  ContactTimings timings_;
};

}  // namespace hapstate
