// Geometrically linear elasticity: W = mu eps:eps + lambda/2 (tr eps)^2, eps = sym(F - I).
// P = 2 mu eps + lambda tr(eps) I (symmetric), A = mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl.
#include "material/laws.h"
#include "material/tensor_ops.h"

namespace hapstate::detail {
namespace {

class Linear final : public Material {
 public:
  Linear(double mu, double lambda) : mu_(mu), lambda_(lambda) {
    const Mat3 I = Mat3::Identity();
    tangent_.setZero();
    add_left_identity(tangent_, mu_, I);
    add_crossed(tangent_, mu_, I, I);
    add_outer(tangent_, lambda_, I, I);
  }

  std::string_view name() const override { return "linear"; }

  double energy(const Mat3& F) const override {
    const Mat3 eps = strain(F);
    const double tr = eps.trace();
    return mu_ * eps.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  double evaluate(const Mat3& F, Mat3* P, Mat9* A) const override {
    const Mat3 eps = strain(F);
    const double tr = eps.trace();
    if (P) *P = 2.0 * mu_ * eps + lambda_ * tr * Mat3::Identity();
    if (A) *A = tangent_;
    return mu_ * eps.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  bool requires_positive_jacobian() const override { return false; }

 private:
  static Mat3 strain(const Mat3& F) { return 0.5 * (F + F.transpose()) - Mat3::Identity(); }

  double mu_, lambda_;
  Mat9 tangent_;
};

}  // namespace

std::unique_ptr<Material> make_linear(double mu, double lambda) {
  return std::make_unique<Linear>(mu, lambda);
}

}  // namespace hapstate::detail
