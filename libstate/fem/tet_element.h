// One linear (P1) tetrahedron in the total Lagrangian setting: reference shape-function
// gradients, volume, and the 12-DOF energy / force / stiffness kernel. Fixed-size, no heap.
#pragma once

#include "material/material.h"

#include <Eigen/Core>

namespace hapstate {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

struct TetGeometry {
  Eigen::Matrix<double, 4, 3> grad;  // row a = reference gradient of shape function N_a [1/m]
  double volume = 0;                 // reference volume [m^3], > 0
};

// Geometry of the tet with reference corners x0..x3 (metres). Precondition: positive volume.
TetGeometry make_tet_geometry(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                              const Eigen::Vector3d& x2, const Eigen::Vector3d& x3);

// Deformation gradient F = I + sum_a u_a grad_a^T for element displacements u_e (node-major:
// u_e[3a + i] = displacement of corner a in direction i).
Mat3 deformation_gradient(const TetGeometry& g, const Vec12& u_e);

// Element energy V*W(F); writes the element force V*dW/du_e and stiffness V*d2W/du_e2 if the
// pointers are non-null. Returns +infinity (outputs untouched) if the material needs det F > 0
// and the element is inverted.
double tet_energy(const TetGeometry& g, const Material& material, const Vec12& u_e, Vec12* force,
                  Mat12* stiffness);

}  // namespace hapstate
