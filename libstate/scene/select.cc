#include "scene/select.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapstate {

std::vector<int> nodes_in_box(const Mesh& mesh, const Box& box) {
  std::vector<int> ids;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = mesh.nodes.col(n);
    if ((x.array() >= box.min.array()).all() && (x.array() <= box.max.array()).all()) {
      ids.push_back(n);
    }
  }
  return ids;
}

std::vector<int> nodes_on_plane(const Mesh& mesh, const PlaneSelector& plane) {
  std::vector<int> ids;
  if (mesh.num_nodes() == 0) return ids;
  const Eigen::Vector3d normal = plane.normal.normalized();
  const double diagonal =
      (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).norm();
  const double tolerance = plane.tolerance.value_or(kPlaneRelativeTolerance * diagonal);
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (std::abs((mesh.nodes.col(n) - plane.point).dot(normal)) <= tolerance) ids.push_back(n);
  }
  return ids;
}

std::vector<int> surface_nodes(const Mesh& mesh) {
  std::vector<int> ids(mesh.surface.data(), mesh.surface.data() + mesh.surface.size());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<bool> used_nodes(const Mesh& mesh) {
  std::vector<bool> used(static_cast<size_t>(mesh.num_nodes()), false);
  for (int i = 0; i < mesh.tets.size(); ++i) used[static_cast<size_t>(mesh.tets.data()[i])] = true;
  return used;
}

int nearest_node(const Mesh& mesh, const Eigen::Vector3d& point) {
  const std::vector<bool> used = used_nodes(mesh);
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (!used[static_cast<size_t>(n)]) continue;
    const double d = (mesh.nodes.col(n) - point).squaredNorm();
    if (d < best_distance) best_distance = d, best = n;
  }
  return best;
}

std::vector<int> surface_nodes_within(const Mesh& mesh, const Eigen::Vector3d& point,
                                      double radius) {
  std::vector<int> ids;
  for (int n : surface_nodes(mesh)) {
    if ((mesh.nodes.col(n) - point).norm() <= radius) ids.push_back(n);
  }
  return ids;
}

}  // namespace hapstate
