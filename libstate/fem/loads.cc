#include "fem/loads.h"

#include <Eigen/Geometry>

namespace hapstate {

Eigen::VectorXd gravity_force(const Eigen::Matrix3Xd& positions_m, const Tets& tets, double density,
                              const Eigen::Vector3d& gravity) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(3 * positions_m.cols());
  for (Eigen::Index e = 0; e < tets.cols(); ++e) {
    const Eigen::Vector3d x0 = positions_m.col(tets(0, e));
    const double volume = (positions_m.col(tets(1, e)) - x0)
                              .cross(positions_m.col(tets(2, e)) - x0)
                              .dot(positions_m.col(tets(3, e)) - x0) /
                          6.0;
    const Eigen::Vector3d share = density * volume / 4.0 * gravity;
    for (int a = 0; a < 4; ++a) force.segment<3>(3 * tets(a, e)) += share;
  }
  return force;
}

int add_surface_springs(const Eigen::Matrix3Xd& positions_m, const Triangles& surface,
                        const std::vector<bool>& selected, double stiffness,
                        const std::array<bool, 3>& dofs, Eigen::VectorXd* spring) {
  if (spring->size() == 0) spring->setZero(3 * positions_m.cols());
  int covered = 0;
  for (Eigen::Index t = 0; t < surface.cols(); ++t) {
    const int a = surface(0, t), b = surface(1, t), c = surface(2, t);
    if (!selected[a] || !selected[b] || !selected[c]) continue;
    const double area = 0.5 * (positions_m.col(b) - positions_m.col(a))
                                  .cross(positions_m.col(c) - positions_m.col(a))
                                  .norm();
    for (int corner : {a, b, c})
      for (int k = 0; k < 3; ++k)
        if (dofs[k]) (*spring)[3 * corner + k] += stiffness * area / 3.0;
    ++covered;
  }
  return covered;
}

}  // namespace hapstate
