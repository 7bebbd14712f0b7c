// Hyperelastic material interface: energy density W(F), first Piola-Kirchhoff stress
// P = dW/dF and its derivative A = dP/dF. Stateless and thread-safe (const methods only).
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>
#include <string_view>

namespace hapstate {

using Mat3 = Eigen::Matrix3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// Flattening of a 3x3 tensor used by Mat9: vec(F)[i + 3*j] = F(i, j) (Eigen's column-major
// storage), so A(i + 3*j, k + 3*l) = d P(i,j) / d F(k,l).
class Material {
 public:
  virtual ~Material() = default;
  // Short lower-case law name, as in law_name().
  virtual std::string_view name() const = 0;
  // W(F) [Pa = J/m^3 of reference volume]. Returns +infinity when det F <= 0 for laws that
  // are undefined there (requires_positive_jacobian(): neohooke, mooney).
  virtual double energy(const Mat3& F) const = 0;
  // Returns W(F) (same value as energy()); writes P = dW/dF [Pa] (if non-null) and
  // A = dP/dF [Pa] (if non-null), exact analytic derivatives. A is symmetric (not necessarily
  // positive definite: stvk under compression). Where W is +infinity (det F <= 0) P and A are
  // set to zero, never NaN; callers must test the returned energy. No heap allocation.
  virtual double evaluate(const Mat3& F, Mat3* P, Mat9* A) const = 0;
  // True if W needs det F > 0 (the solver treats J <= 0 as an inverted element).
  virtual bool requires_positive_jacobian() const = 0;
};

enum class Law { kLinear, kStvk, kNeoHooke, kMooney };

// Constants of every law. linear/stvk use mu, lambda; neohooke uses c10, d1;
// mooney uses c10, c01, d1 (Abaqus/CalculiX forms, docs/mechanics.md and docs/calculix.md).
struct MaterialConstants {
  Law law = Law::kStvk;
  double mu = 0, lambda = 0;        // Pa
  double c10 = 0, c01 = 0, d1 = 0;  // Pa, Pa, 1/Pa
};

// Constants from Young's modulus E [Pa] and Poisson's ratio nu (-1 < nu < 0.5):
// mu = E/(2(1+nu)), lambda = E nu/((1+nu)(1-2nu)), K = E/(3(1-2nu)), d1 = 2/K;
// neohooke: c10 = mu/2. mooney: the same small-strain shear modulus, c10 + c01 = mu/2, split
// c10 = 0.8 * mu/2, c01 = 0.2 * mu/2 (documented default; give c10, c01, d1 to choose).
// Throws InputError naming the parameter and its allowed range if E <= 0 or nu is outside
// (-1, 0.5). mu, lambda, c10 and d1 are filled whatever the law (c01 only for mooney).
MaterialConstants constants_from_young_poisson(Law law, double young, double poisson);

// Share of mu/2 given to c10 by constants_from_young_poisson for mooney (c01 gets the rest).
inline constexpr double kMooneyC10Share = 0.8;

// Builds the law named by c.law from the constants it uses. Throws InputError (naming the
// parameter and allowed range) unless they are finite and: linear/stvk mu > 0 and
// lambda > -2/3 mu (positive bulk modulus); neohooke c10 > 0, d1 > 0; mooney additionally
// c01 >= 0. The result is immutable and may be shared between threads.
std::unique_ptr<Material> make_material(const MaterialConstants& c);

// "linear", "stvk", "neohooke", "mooney".
std::string_view law_name(Law law);

// Inverse of law_name(); throws InputError listing the known names for anything else.
Law law_from_name(std::string_view name);

}  // namespace hapstate
