// St. Venant-Kirchhoff: W = mu E:E + lambda/2 (tr E)^2, E = (F^T F - I)/2,
// S = lambda tr(E) I + 2 mu E, P = F S,
// A_ijkl = d_ik S_lj + lambda F_ij F_kl + mu (F_il F_kj + (F F^T)_ik d_jl).
#include "material/laws.h"
#include "material/tensor_ops.h"

namespace hapstate::detail {
namespace {

class Stvk final : public Material {
 public:
  Stvk(double mu, double lambda) : mu_(mu), lambda_(lambda) {}

  std::string_view name() const override { return "stvk"; }

  double energy(const Mat3& F) const override {
    const Mat3 E = green_strain(F);
    const double tr = E.trace();
    return mu_ * E.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  double evaluate(const Mat3& F, Mat3* P, Mat9* A) const override {
    const Mat3 E = green_strain(F);
    const double tr = E.trace();
    if (P || A) {
      const Mat3 S = lambda_ * tr * Mat3::Identity() + 2.0 * mu_ * E;
      if (P) P->noalias() = F * S;
      if (A) {
        A->setZero();
        add_left_identity(*A, 1.0, S);
        add_outer(*A, lambda_, F, F);
        add_crossed(*A, mu_, F, F);
        add_right_identity(*A, mu_, F * F.transpose());
      }
    }
    return mu_ * E.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  bool requires_positive_jacobian() const override { return false; }

 private:
  static Mat3 green_strain(const Mat3& F) { return 0.5 * (F.transpose() * F - Mat3::Identity()); }

  double mu_, lambda_;
};

}  // namespace

std::unique_ptr<Material> make_stvk(double mu, double lambda) {
  return std::make_unique<Stvk>(mu, lambda);
}

}  // namespace hapstate::detail
