#include "scene/rigid_modes.h"

#include <Eigen/Dense>

#include <numeric>
#include <sstream>

namespace hapstate {
namespace {

using Matrix6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

int find_root(std::vector<int>& parent, int n) {
  while (parent[n] != n) n = parent[n] = parent[parent[n]];
  return n;
}

// Prints v with 4 significant digits; components below `zero` print as 0.
std::string format_vector(const Eigen::Vector3d& v, double zero = 1e-12) {
  const Eigen::Vector3d w = (v.array().abs() < zero).select(0.0, v);
  std::ostringstream os;
  os.precision(4);
  os << "(" << w[0] << ", " << w[1] << ", " << w[2] << ")";
  return os.str();
}

// "x", "y", "z" for a coordinate axis, otherwise the unit direction (sign chosen so that its
// first non-zero component is positive).
std::string axis_name(const Eigen::Vector3d& direction) {
  Eigen::Vector3d d = direction.normalized();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) > 1e-9) {
      if (d[k] < 0) d = -d;
      break;
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (std::abs(std::abs(d[k]) - 1.0) < 1e-9) return std::string(1, "xyz"[k]);
  }
  return format_vector(d);
}

// Describes one free motion from the null space `null` (6 x k) of the scaled mode matrix:
// a pure translation along an axis if one is free, else a rotation about an axis through a
// point (about x, y or z if possible). Mode v = (a, w): u(X) = a + w x (X - c) / scale.
std::string describe(const Matrix6X& null, const Eigen::Vector3d& centroid, double scale) {
  constexpr double kTolerance = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Vector6 t = Vector6::Unit(k);
    if ((t - null * (null.transpose() * t)).norm() < kTolerance) {
      return std::string("translation along ") + "xyz"[k];
    }
  }
  const Eigen::Matrix3Xd rotation = null.bottomRows(3);
  auto rotation_about = [&](const Vector6& v) {
    const Eigen::Vector3d a = v.head<3>();
    const Eigen::Vector3d w = v.tail<3>() / scale;  // actual angular velocity
    const Eigen::Vector3d through = centroid + w.cross(a) / w.squaredNorm();
    return "rotation about " + axis_name(w) + " through " + format_vector(through, 1e-9 * scale);
  };
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    const Eigen::VectorXd c = rotation.completeOrthogonalDecomposition().solve(e);
    if ((rotation * c - e).norm() < kTolerance) return rotation_about(null * c);
  }
  const Vector6 v = null.col(0);
  if (v.tail<3>().norm() < kTolerance) return "translation along " + axis_name(v.head<3>());
  return rotation_about(v);
}

}  // namespace

std::vector<std::vector<int>> connected_components(const Mesh& mesh) {
  const int n = mesh.num_nodes();
  std::vector<int> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> used(static_cast<size_t>(n), false);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int a = find_root(parent, mesh.tets(0, t));
    used[static_cast<size_t>(mesh.tets(0, t))] = true;
    for (int i = 1; i < 4; ++i) {
      used[static_cast<size_t>(mesh.tets(i, t))] = true;
      const int b = find_root(parent, mesh.tets(i, t));
      if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
    }
  }
  // After unions toward the smaller id, a root is the smallest node of its component.
  std::vector<std::vector<int>> components;
  std::vector<int> index_of_root(static_cast<size_t>(n), -1);
  for (int node = 0; node < n; ++node) {
    if (!used[static_cast<size_t>(node)]) continue;
    const int root = find_root(parent, node);
    if (index_of_root[static_cast<size_t>(root)] < 0) {
      index_of_root[static_cast<size_t>(root)] = static_cast<int>(components.size());
      components.emplace_back();
    }
    components[static_cast<size_t>(index_of_root[static_cast<size_t>(root)])].push_back(node);
  }
  return components;
}

std::vector<FreeRigidModes> free_rigid_modes(const Mesh& mesh, const std::vector<DofRole>& role) {
  std::vector<FreeRigidModes> result;
  const auto components = connected_components(mesh);
  for (size_t index = 0; index < components.size(); ++index) {
    const std::vector<int>& nodes = components[index];
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int n : nodes) centroid += mesh.nodes.col(n);
    centroid /= static_cast<double>(nodes.size());
    double scale = 0;
    for (int n : nodes) scale = std::max(scale, (mesh.nodes.col(n) - centroid).norm());
    if (scale == 0) scale = 1;

    std::vector<Eigen::Matrix<double, 1, 6>> rows;
    for (int n : nodes) {
      const Eigen::Vector3d r = (mesh.nodes.col(n) - centroid) / scale;
      for (int k = 0; k < 3; ++k) {
        if (role[3 * static_cast<size_t>(n) + static_cast<size_t>(k)] == DofRole::kFree) continue;
        Eigen::Matrix<double, 1, 6> row = Eigen::Matrix<double, 1, 6>::Zero();
        row[k] = 1;  // translation e_k
        for (int j = 0; j < 3; ++j) {
          row[3 + j] = Eigen::Vector3d::Unit(j).cross(r)[k];  // rotation about e_j
        }
        rows.push_back(row);
      }
    }
    Eigen::Matrix<double, Eigen::Dynamic, 6> modes(static_cast<Eigen::Index>(rows.size()), 6);
    for (size_t i = 0; i < rows.size(); ++i) modes.row(static_cast<Eigen::Index>(i)) = rows[i];

    // Null space: right singular vectors of the small singular values (and of the missing
    // ones when there are fewer than 6 rows).
    Eigen::Matrix<double, 6, 6> v = Eigen::Matrix<double, 6, 6>::Identity();
    Vector6 sigma = Vector6::Zero();
    if (!rows.empty()) {
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Eigen::MatrixXd(modes), Eigen::ComputeFullV);
      v = svd.matrixV();
      sigma.head(svd.singularValues().size()) = svd.singularValues();
    }
    const double threshold = kRigidRankTolerance * sigma[0];
    std::vector<int> free;
    for (int i = 0; i < 6; ++i) {
      if (sigma[i] <= threshold) free.push_back(i);
    }
    if (free.empty()) continue;
    Matrix6X null(6, static_cast<Eigen::Index>(free.size()));
    for (size_t i = 0; i < free.size(); ++i)
      null.col(static_cast<Eigen::Index>(i)) = v.col(free[i]);
    result.push_back({static_cast<int>(index), static_cast<int>(nodes.size()),
                      static_cast<int>(free.size()), describe(null, centroid, scale)});
  }
  return result;
}

}  // namespace hapstate
