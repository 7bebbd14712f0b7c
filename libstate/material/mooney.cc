// Compressible Mooney-Rivlin (Abaqus/CalculiX):
// W = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1.
// Undefined for J <= 0: energy +infinity, P and A zero.
#include "material/invariant_terms.h"
#include "material/laws.h"

namespace hapstate::detail {
namespace {

class Mooney final : public Material {
 public:
  Mooney(double c10, double c01, double d1) : c10_(c10), c01_(c01), d1_(d1) {}

  std::string_view name() const override { return "mooney"; }

  double energy(const Mat3& F) const override { return evaluate(F, nullptr, nullptr); }

  double evaluate(const Mat3& F, Mat3* P, Mat9* A) const override {
    const Kinematics k(F);
    if (!(k.j > 0)) return inverted_result(P, A);
    if (P) P->setZero();
    if (A) A->setZero();
    return add_i1bar_term(k, c10_, P, A) + add_i2bar_term(k, c01_, P, A) +
           add_volumetric_term(k, d1_, P, A);
  }

  bool requires_positive_jacobian() const override { return true; }

 private:
  double c10_, c01_, d1_;
};

}  // namespace

std::unique_ptr<Material> make_mooney(double c10, double c01, double d1) {
  return std::make_unique<Mooney>(c10, c01, d1);
}

}  // namespace hapstate::detail
