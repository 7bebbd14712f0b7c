// Shared helpers of the material tests: the laws under test, random deformation gradients and
// fourth-order central finite differences.
#pragma once

#include "material/material.h"

#include <Eigen/Geometry>

#include <random>
#include <string>
#include <vector>

namespace hapstate::test {

inline constexpr double kYoung = 5000.0;  // Pa, soft-tissue order of magnitude

// One material configuration under test, with a readable label.
struct Case {
  std::string label;
  MaterialConstants constants;
};

// Every law from (kYoung, nu) for nu in a sweep 0 .. 0.49, plus a mooney with a dominant c01.
inline std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (Law law : {Law::kLinear, Law::kStvk, Law::kNeoHooke, Law::kMooney}) {
    for (double nu : {0.0, 0.2, 0.3, 0.45, 0.49}) {
      cases.push_back({std::string(law_name(law)) + "_nu" + std::to_string(nu),
                       constants_from_young_poisson(law, kYoung, nu)});
    }
  }
  MaterialConstants m;
  m.law = Law::kMooney;
  m.c10 = 100.0;
  m.c01 = 900.0;
  m.d1 = 1e-3;
  cases.push_back({"mooney_c01_dominant", m});
  return cases;
}

// Uniformly random rotation (normalised Gaussian quaternion).
inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// F = Q (I + H), entries of H uniform in [-strain, strain]; for strain <= 0.3 the Frobenius
// norm of H is below 1, so det F > 0. rotate = false gives Q = I.
inline Mat3 random_deformation(std::mt19937& rng, double strain, bool rotate) {
  std::uniform_real_distribution<double> u(-strain, strain);
  Mat3 H;
  for (int i = 0; i < 9; ++i) H.data()[i] = u(rng);
  const Mat3 stretch = Mat3::Identity() + H;
  return rotate ? Mat3(random_rotation(rng) * stretch) : stretch;
}

// Fourth-order central difference of a scalar/matrix valued f along the (i, j) entry of F.
template <class Fn>
auto central_difference(const Fn& f, const Mat3& F, int i, int j, double h) {
  auto at = [&](double t) {
    Mat3 G = F;
    G(i, j) += t;
    return f(G);
  };
  // Evaluated here: for a matrix f the expression refers to the temporaries at(...), which die
  // at the end of this statement (returning the unevaluated Eigen expression read freed stack:
  // found by AddressSanitizer).
  using Result = decltype(f(F));
  return Result((8.0 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12.0 * h));
}

// GoogleTest parameter name of a Case: its label with '.' replaced by '_'.
struct CaseName {
  template <class Info>
  std::string operator()(const Info& info) const {
    std::string s = info.param.label;
    for (char& c : s)
      if (c == '.') c = '_';
    return s;
  }
};

}  // namespace hapstate::test
