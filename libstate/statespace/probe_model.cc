#include "statespace/probe_model.h"

#include "mesh/winding_number.h"
#include "solver/sphere_query.h"
#include "solver/triangle_distance.h"
#include "util/error.h"

#include <algorithm>

namespace hapstate {
namespace {

Eigen::VectorXd metres(const std::vector<double>& u, double unit) {
  return Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size())) * unit;
}

// The body's surface as it rests: the mesh's nodes carried by the loaded rest state (the mesh
// as drawn without loads). What a contact probe at rest can touch.
Mesh rest_shape(const Problem& problem) {
  Mesh shape;
  shape.nodes = problem.mesh.nodes;
  shape.surface = problem.mesh.surface;
  if (problem.rest_m.size() == 3 * problem.mesh.num_nodes())
    shape.nodes +=
        Eigen::Map<const Eigen::Matrix3Xd>(problem.rest_m.data(), 3, problem.mesh.num_nodes()) /
        problem.unit;
  return shape;
}

// Whether a point is inside the body at rest, and the signed clearance of a contact probe
// (ProbeModel::clearance): inside is the winding number of the rest surface above 1/2. Built
// with the probe (the expansion's threads ask at once); O(surface triangles) a query, asked only
// where no surface triangle (node) is within the sphere's reach.
class RestInside {
 public:
  explicit RestInside(const Mesh& mesh) : winding_(mesh.nodes, mesh.surface) {}
  // `nearest`: the nearest surface point (sliding) or candidate node (sticking) within `range`
  // of the sphere, `reach` the radius (sticking: the reach). Outside the rest body the distance
  // to it minus `reach`, gradient the unit vector from it to p; inside minus the distance minus
  // `reach` (deeper is more negative), gradient the unit vector from p to it. None within range:
  // `range` outside, -(range + reach) inside, gradient 0.
  ProbeModel::Clearance clearance(const Eigen::Vector3d& p,
                                  const std::optional<Eigen::Vector3d>& nearest, double reach,
                                  double range) const {
    const bool in = inside(p);
    if (!nearest) return {in ? -(range + reach) : range, Eigen::Vector3d::Zero()};
    const Eigen::Vector3d d = p - *nearest;
    const double dist = d.norm();
    const Eigen::Vector3d unit = dist > 0 ? Eigen::Vector3d(d / dist) : Eigen::Vector3d::Zero();
    if (in) return {-dist - reach, -unit};
    return {dist - reach, unit};
  }
  bool inside(const Eigen::Vector3d& p) const { return winding_(p) > 0.5; }

 private:
  WindingNumber winding_;
};

class GrabProbe final : public ProbeModel {
 public:
  explicit GrabProbe(const Problem& problem) : problem_(problem) {
    const auto& role = problem.constraints.role;
    for (int d = 0; d < static_cast<int>(role.size()); ++d)
      if (role[d] == DofRole::kProbe) dofs_.push_back(d);
  }

  Eigen::Vector3d rest_position() const override { return problem_.probe_rest; }

  ProbeLoad load_of(const PathSolver&, const Eigen::Vector3d& p) const override {
    const Eigen::Vector3d t = p - problem_.probe_rest;
    ProbeLoad load;
    load.dofs = dofs_;
    for (int d : dofs_) load.values.push_back(t[d % 3]);
    return load;
  }

  void set_state(PathSolver& solver, const ConfigVectors& v,
                 const Eigen::Vector3d& p) const override {
    solver.set_state(metres(v.u, problem_.unit), p - problem_.probe_rest);
  }

  bool clear_of_body(const Eigen::Vector3d&) const override { return false; }
  bool trivial_move(const Eigen::Vector3d&, const Eigen::Vector3d&) const override { return false; }
  std::optional<Clearance> clearance(const Eigen::Vector3d&, double) const override {
    return std::nullopt;
  }
  VectorLayout layout() const override {
    return {false, static_cast<int>(dofs_.size()), static_cast<int>(dofs_.size())};
  }

 private:
  const Problem& problem_;
  std::vector<int> dofs_;
};

// The contact sphere (solver/contact_set.h). "Touches" uses the solver's own criterion: a
// node deeper inside the sphere than the penetration tolerance.
class ContactProbe final : public ProbeModel {
 public:
  explicit ContactProbe(const Problem& problem)
      : problem_(problem),
        shape_(rest_shape(problem)),
        reach_(problem.contact->radius * (1.0 - kPenetrationTolerance)) {
    const auto& candidates = problem.contact->candidates;
    rest_.resize(3, static_cast<Eigen::Index>(candidates.size()));
    for (std::size_t k = 0; k < candidates.size(); ++k)
      rest_.col(static_cast<Eigen::Index>(k)) = shape_.nodes.col(candidates[k]);
    index_.build(rest_, problem.contact->radius);
  }

  Eigen::Vector3d rest_position() const override { return problem_.probe_rest; }

  ProbeLoad load_of(const PathSolver& solver, const Eigen::Vector3d&) const override {
    ProbeLoad load;
    const Eigen::Matrix3Xd u = solver.displacements();
    for (int n : solver.touched_nodes())
      for (int c = 0; c < 3; ++c) {
        load.dofs.push_back(3 * n + c);
        load.values.push_back(u(c, n));
      }
    return load;
  }

  void set_state(PathSolver& solver, const ConfigVectors& v,
                 const Eigen::Vector3d& p) const override {
    solver.set_state(metres(v.u, problem_.unit), p - problem_.probe_rest, v.touched);
  }

  bool clear_of_body(const Eigen::Vector3d& p) const override {
    std::vector<int> near;
    index_.inside(p, reach_, &near);
    return near.empty() && !inside_.inside(p);
  }

  bool trivial_move(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override {
    if (!clear_of_body(a) || !clear_of_body(b)) return false;
    // Nodes near the segment: within reach + half its length of its midpoint.
    const Eigen::Vector3d ab = b - a;
    if (ab.squaredNorm() == 0.0) return true;
    std::vector<int> near;
    index_.inside(0.5 * (a + b), reach_ + 0.5 * ab.norm(), &near);
    for (int k : near) {
      const Eigen::Vector3d x = rest_.col(k);
      const double s = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      if ((x - (a + s * ab)).norm() < reach_) return false;
    }
    return true;
  }
  std::optional<Clearance> clearance(const Eigen::Vector3d& p, double range) const override {
    std::vector<int> near;
    index_.inside(p, reach_ + range, &near);
    std::optional<Eigen::Vector3d> nearest;
    for (int k : near)
      if (!nearest || (p - rest_.col(k)).norm() < (p - *nearest).norm()) nearest = rest_.col(k);
    return inside_.clearance(p, nearest, reach_, range);
  }
  VectorLayout layout() const override { return {true, 0, 0}; }

 private:
  const Problem& problem_;
  Mesh shape_;  // the body in its rest state
  double reach_;
  Eigen::Matrix3Xd rest_;  // rest positions of the candidate nodes
  SphereQuery index_;
  RestInside inside_{shape_};
};

// Frictionless contact (solver/sliding_contact.h). "Touches" uses the solver's own criterion:
// a surface triangle closer to the centre than the radius. Triangles are found through a grid
// hash of their centroids (cell = radius), queried with the radius plus the largest distance
// of a corner from its centroid.
class SlidingProbe final : public ProbeModel {
 public:
  explicit SlidingProbe(const Problem& problem)
      : problem_(problem), shape_(rest_shape(problem)), radius_(problem.contact->radius) {
    const Triangles& tri = shape_.surface;
    centroids_.resize(3, tri.cols());
    for (int t = 0; t < tri.cols(); ++t) {
      Eigen::Vector3d m = Eigen::Vector3d::Zero();
      for (int i = 0; i < 3; ++i) m += shape_.nodes.col(tri(i, t)) / 3.0;
      centroids_.col(t) = m;
      for (int i = 0; i < 3; ++i)
        spread_ = std::max(spread_, (shape_.nodes.col(tri(i, t)) - m).norm());
    }
    index_.build(centroids_, std::max(radius_, spread_));
  }

  Eigen::Vector3d rest_position() const override { return problem_.probe_rest; }
  ProbeLoad load_of(const PathSolver&, const Eigen::Vector3d&) const override { return {}; }

  void set_state(PathSolver& solver, const ConfigVectors& v,
                 const Eigen::Vector3d& p) const override {
    solver.set_state(metres(v.u, problem_.unit), p - problem_.probe_rest, {}, v.multipliers);
  }

  bool clear_of_body(const Eigen::Vector3d& p) const override {
    return sweeps_past(p, p) && !inside_.inside(p);
  }

  // Both ends clear of the body: the segment farther than the radius from every surface
  // triangle, so it does not cross the surface and b is outside the body wherever a is.
  bool trivial_move(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override {
    return sweeps_past(a, b) && !inside_.inside(a);
  }
  std::optional<Clearance> clearance(const Eigen::Vector3d& p, double range) const override {
    std::vector<int> near;
    index_.inside(p, radius_ + spread_ + range, &near);
    const Triangles& tri = shape_.surface;
    const Eigen::Matrix3Xd& x = shape_.nodes;
    std::optional<Eigen::Vector3d> nearest;
    for (int t : near) {
      const TrianglePoint tp =
          closest_point(x.col(tri(0, t)), x.col(tri(1, t)), x.col(tri(2, t)), p);
      if (!nearest || tp.distance < (p - *nearest).norm()) nearest = tp.closest;
    }
    return inside_.clearance(p, nearest, radius_, range);
  }
  std::optional<RestSurface> rest_surface() const override {
    RestSurface out;
    out.radius = radius_;
    const Triangles& tri = shape_.surface;
    for (Eigen::Index t = 0; t < tri.cols(); ++t)
      for (int i = 0; i < 3; ++i)
        for (int a = 0; a < 3; ++a) out.triangles.push_back(shape_.nodes(a, tri(i, t)));
    return out;
  }
  VectorLayout layout() const override { return {false, 0, 3, true}; }

 private:
  // The segment from a to b farther than the radius from every rest surface triangle.
  bool sweeps_past(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    std::vector<int> near;
    index_.inside(0.5 * (a + b), radius_ + spread_ + 0.5 * (b - a).norm(), &near);
    const Triangles& tri = shape_.surface;
    const Eigen::Matrix3Xd& x = shape_.nodes;
    for (int t : near) {
      const double d =
          segment_triangle_distance(a, b, x.col(tri(0, t)), x.col(tri(1, t)), x.col(tri(2, t)));
      if (d < radius_) return false;
    }
    return true;
  }

  const Problem& problem_;
  Mesh shape_;  // the body in its rest state
  double radius_;
  double spread_ = 0;           // largest distance of a triangle corner from its centroid
  Eigen::Matrix3Xd centroids_;  // rest centroids of the surface triangles
  SphereQuery index_;
  RestInside inside_{shape_};
};

}  // namespace

std::unique_ptr<ProbeModel> make_probe_model(const Problem& problem) {
  if (problem.contact && problem.contact->friction == Friction::kNone)
    return std::make_unique<SlidingProbe>(problem);
  if (problem.contact) return std::make_unique<ContactProbe>(problem);
  return std::make_unique<GrabProbe>(problem);
}

}  // namespace hapstate
