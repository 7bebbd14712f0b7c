// Global assembly of the total potential energy Pi(u) = sum_e V_e W(F_e) (plus the body loads'
// terms, fem/loads.h, when set), the internal force f = dPi/du and the tangent stiffness
// K = d2Pi/du2 of a P1 tetrahedral mesh.
// K is stored as the upper triangle (row <= col) of a compressed-column matrix whose pattern
// and element scatter map are computed once in the constructor. Not thread-safe: one
// Assembler per worker thread (it is cheap to copy).
#pragma once

#include "fem/loads.h"
#include "fem/tet_element.h"
#include "material/material.h"
#include "mesh/mesh.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace hapstate {

// Upper-triangular compressed-column pattern of a symmetric matrix.
struct SymmetricPattern {
  int n = 0;
  std::vector<int> col_ptr;  // size n + 1
  std::vector<int> row_idx;  // size nnz, sorted within each column, row <= column
  std::vector<int> diag;     // index of the diagonal entry of each column
  int nnz() const { return static_cast<int>(row_idx.size()); }
};

// y = K x for K given by its upper triangle (pattern, values).
void symmetric_multiply(const SymmetricPattern& pattern, const std::vector<double>& values,
                        const Eigen::VectorXd& x, Eigen::VectorXd* y);

class Assembler {
 public:
  // positions_m: reference node positions in metres; tets positively oriented.
  // The material must outlive the assembler.
  Assembler(const Eigen::Matrix3Xd& positions_m, const Tets& tets, const Material& material);

  int num_dofs() const { return pattern_.n; }
  const SymmetricPattern& pattern() const { return pattern_; }
  const Material& material() const { return *material_; }

  // Pi(u) [J]; +infinity if an element is inverted for a law that needs det F > 0.
  double energy(const Eigen::VectorXd& u) const;
  // Pi(u) and f = dPi/du [N] (f resized). f is left undefined when Pi is infinite.
  double energy_and_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const;
  // Pi(u), f and the values of K (upper triangle, pattern() order). With project_psd, each
  // element stiffness is replaced by its projection onto the positive semi-definite cone (a
  // descent direction for indefinite tangents; used as a fallback).
  double energy_force_tangent(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                              std::vector<double>* k_values, bool project_psd = false) const;
  // Threads for the element terms of energy_force_tangent (OpenMP; default 1). The results do
  // not depend on it. With more than one, energy_force_tangent uses buffers of the assembler
  // (about 730 bytes per tet): not to be called concurrently on one assembler.
  void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
  // The body force and supports (fem/loads.h) added to every energy, force and tangent; the
  // loads must outlive the assembler (nullptr or empty: none). scale multiplies the body force
  // only (incremental loading; 1 by default).
  void set_loads(const BodyLoads* loads) { loads_ = loads && !loads->empty() ? loads : nullptr; }
  void set_load_scale(double scale) { load_scale_ = scale; }
  // ||s b||: the scaled body force's norm [N] (0 without one), a scale for residuals.
  double load_norm() const {
    return loads_ && loads_->has_force() ? load_scale_ * loads_->force.norm() : 0.0;
  }

 private:
  double energy_force_tangent_parallel(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                                       std::vector<double>* k_values, bool project_psd) const;
  void gather(const Eigen::VectorXd& u, int e, Vec12* u_e) const;
  // Adds the loads' energy, force and tangent (diagonal) at u; f / k_values may be null.
  double add_loads(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                   std::vector<double>* k_values) const;
  static void upper_triangle(const Mat12& k_e, std::array<double, 78>* upper);
  // Adds element e's force and stiffness (upper triangle) into the global f and K.
  void scatter(int e, const Vec12& f_e, const std::array<double, 78>& k_upper, Eigen::VectorXd* f,
               std::vector<double>* k_values) const;

  Tets tets_;
  const Material* material_;
  std::vector<TetGeometry> geometry_;
  SymmetricPattern pattern_;
  // For element e and local pair (p <= q) in row-major upper order (78 entries), the index into
  // the value array of global entry (min(dof p, dof q), max(...)).
  std::vector<std::array<int, 78>> scatter_;
  int threads_ = 1;
  const BodyLoads* loads_ = nullptr;
  double load_scale_ = 1.0;
  // energy_force_tangent_parallel's per-element results.
  mutable std::vector<double> element_w_;
  mutable std::vector<Vec12> element_f_;
  mutable std::vector<std::array<double, 78>> element_k_;
};

}  // namespace hapstate
