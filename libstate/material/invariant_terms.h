// Internal building blocks of the invariant-based laws (Abaqus/CalculiX forms):
// isochoric terms in I1bar = J^(-2/3) tr C and I2bar = J^(-4/3) ((tr C)^2 - tr(C^2))/2, and the
// volumetric term (J - 1)^2 / D1. Each returns its energy and adds its share to P and A
// (when non-null); the caller zeroes P and A first. All require J > 0.
#pragma once

#include "material/material.h"

namespace hapstate::detail {

// Quantities of F shared by the terms. Valid (all terms defined) only if j > 0.
struct Kinematics {
  explicit Kinematics(const Mat3& F);
  const Mat3& f;
  double j;    // det F
  double i1;   // tr C = F:F
  Mat3 inv_t;  // F^{-T} (only set if j > 0)
};

// c10 (I1bar - 3).
double add_i1bar_term(const Kinematics& k, double c10, Mat3* P, Mat9* A);
// c01 (I2bar - 3).
double add_i2bar_term(const Kinematics& k, double c01, Mat3* P, Mat9* A);
// (J - 1)^2 / d1.
double add_volumetric_term(const Kinematics& k, double d1, Mat3* P, Mat9* A);

// Common evaluate() path for J <= 0: zero P and A (if non-null), return +infinity.
double inverted_result(Mat3* P, Mat9* A);

}  // namespace hapstate::detail
