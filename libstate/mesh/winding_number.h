// Generalized winding number of a triangle surface (Jacobson, Kavan, Sorkine-Hornung 2013): the
// sum of the signed solid angles its triangles subtend at a point, divided by 4*pi. For a closed,
// outward-oriented surface it is 1 inside and 0 outside; where the surface folds through itself
// it counts the layers (2, -1, ...), and small gaps only blur it near the gap. Used by the
// carving fallback (carve.h) to decide which grid tets lie inside.
#pragma once

#include "mesh/mesh.h"
#include "mesh/surface.h"

#include <Eigen/Core>

#include <vector>

namespace hapstate {

class WindingNumber {
 public:
  explicit WindingNumber(const TriangleSurface& s);
  // The surface triangles `faces` of nodes `xyz` (a Mesh's nodes and surface, mesh units).
  WindingNumber(const Eigen::Matrix3Xd& xyz, const Triangles& faces);

  // Winding number at `p` (exact sum over all triangles; O(faces)). 0 at a surface vertex's
  // own triangles' corners (their solid angle is taken as 0).
  double operator()(const Eigen::Vector3d& p) const;

  // Signed volume enclosed by the surface, sum of a.(b x c)/6 over its triangles: the integral
  // of the winding number over space (negative for an inward-oriented surface).
  double enclosed_volume() const { return volume_; }

 private:
  // Adds the last triangle of corners_ to volume_.
  void add_volume();
  std::vector<double> corners_;  // 9 coordinates per triangle
  double volume_ = 0;
};

}  // namespace hapstate
