#include "fem/assembler.h"

#include "util/error.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace hapstate {
namespace {

SymmetricPattern build_pattern(int num_nodes, const Tets& tets) {
  // Node adjacency (node-level), then expand each node pair into 3x3 DOF blocks.
  std::vector<std::vector<int>> adjacent(num_nodes);
  for (int e = 0; e < tets.cols(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (tets(a, e) <= tets(b, e)) adjacent[tets(b, e)].push_back(tets(a, e));
  for (int n = 0; n < num_nodes; ++n) {
    adjacent[n].push_back(n);  // every DOF has a diagonal entry, even an unreferenced node's
    std::sort(adjacent[n].begin(), adjacent[n].end());
    adjacent[n].erase(std::unique(adjacent[n].begin(), adjacent[n].end()), adjacent[n].end());
  }
  SymmetricPattern p;
  p.n = 3 * num_nodes;
  p.col_ptr.assign(p.n + 1, 0);
  p.diag.assign(p.n, -1);
  for (int col_node = 0; col_node < num_nodes; ++col_node) {
    for (int k = 0; k < 3; ++k) {
      const int col = 3 * col_node + k;
      for (int row_node : adjacent[col_node]) {
        for (int i = 0; i < 3; ++i) {
          const int row = 3 * row_node + i;
          if (row > col) continue;
          if (row == col) p.diag[col] = static_cast<int>(p.row_idx.size());
          p.row_idx.push_back(row);
        }
      }
      p.col_ptr[col + 1] = static_cast<int>(p.row_idx.size());
    }
  }
  return p;
}

int find_entry(const SymmetricPattern& p, int row, int col) {
  const auto first = p.row_idx.begin() + p.col_ptr[col];
  const auto last = p.row_idx.begin() + p.col_ptr[col + 1];
  const auto it = std::lower_bound(first, last, row);
  return static_cast<int>(it - p.row_idx.begin());
}

void project_to_psd(Mat12* k) {
  Eigen::SelfAdjointEigenSolver<Mat12> eig(*k);
  Vec12 lambda = eig.eigenvalues().cwiseMax(0.0);
  *k = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

void symmetric_multiply(const SymmetricPattern& pattern, const std::vector<double>& values,
                        const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  y->setZero(pattern.n);
  for (int col = 0; col < pattern.n; ++col) {
    for (int k = pattern.col_ptr[col]; k < pattern.col_ptr[col + 1]; ++k) {
      const int row = pattern.row_idx[k];
      (*y)[row] += values[k] * x[col];
      if (row != col) (*y)[col] += values[k] * x[row];
    }
  }
}

Assembler::Assembler(const Eigen::Matrix3Xd& positions_m, const Tets& tets,
                     const Material& material)
    : tets_(tets), material_(&material) {
  const int num_nodes = static_cast<int>(positions_m.cols());
  geometry_.reserve(tets.cols());
  for (int e = 0; e < tets.cols(); ++e) {
    geometry_.push_back(make_tet_geometry(positions_m.col(tets(0, e)), positions_m.col(tets(1, e)),
                                          positions_m.col(tets(2, e)),
                                          positions_m.col(tets(3, e))));
    if (!(geometry_.back().volume > 0.0)) {
      throw InputError("tetrahedron " + std::to_string(e) +
                       " has non-positive reference volume (mesh not validated?)");
    }
  }
  pattern_ = build_pattern(num_nodes, tets);
  scatter_.resize(tets.cols());
  for (int e = 0; e < tets.cols(); ++e) {
    int slot = 0;
    for (int p = 0; p < 12; ++p) {
      for (int q = p; q < 12; ++q) {
        const int dp = 3 * tets(p / 3, e) + p % 3;
        const int dq = 3 * tets(q / 3, e) + q % 3;
        scatter_[e][slot++] = find_entry(pattern_, std::min(dp, dq), std::max(dp, dq));
      }
    }
  }
}

// The element stiffness's upper triangle, row-major (the order of scatter_).
void Assembler::upper_triangle(const Mat12& k_e, std::array<double, 78>* upper) {
  int slot = 0;
  for (int p = 0; p < 12; ++p)
    for (int q = p; q < 12; ++q) (*upper)[slot++] = k_e(p, q);
}

void Assembler::scatter(int e, const Vec12& f_e, const std::array<double, 78>& k_upper,
                        Eigen::VectorXd* f, std::vector<double>* k_values) const {
  for (int a = 0; a < 4; ++a) f->segment<3>(3 * tets_(a, e)) += f_e.segment<3>(3 * a);
  const std::array<int, 78>& map = scatter_[e];
  for (int slot = 0; slot < 78; ++slot) (*k_values)[map[slot]] += k_upper[slot];
}

void Assembler::gather(const Eigen::VectorXd& u, int e, Vec12* u_e) const {
  for (int a = 0; a < 4; ++a) u_e->segment<3>(3 * a) = u.segment<3>(3 * tets_(a, e));
}

double Assembler::add_loads(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                            std::vector<double>* k_values) const {
  double energy = 0;
  if (loads_->has_force()) {
    energy -= load_scale_ * loads_->force.dot(u);
    if (f) *f -= load_scale_ * loads_->force;
  }
  if (loads_->has_springs()) {
    for (int d = 0; d < pattern_.n; ++d) {
      const double k = loads_->spring[d];
      if (k == 0.0) continue;
      energy += 0.5 * k * u[d] * u[d];
      if (f) (*f)[d] += k * u[d];
      if (k_values) (*k_values)[pattern_.diag[d]] += k;
    }
  }
  return energy;
}

double Assembler::energy(const Eigen::VectorXd& u) const {
  double total = 0;
  Vec12 u_e;
  for (int e = 0; e < static_cast<int>(geometry_.size()); ++e) {
    gather(u, e, &u_e);
    total += tet_energy(geometry_[e], *material_, u_e, nullptr, nullptr);
  }
  if (loads_ && std::isfinite(total)) total += add_loads(u, nullptr, nullptr);
  return total;
}

double Assembler::energy_and_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const {
  f->setZero(pattern_.n);
  double total = 0;
  Vec12 u_e, f_e;
  for (int e = 0; e < static_cast<int>(geometry_.size()); ++e) {
    gather(u, e, &u_e);
    const double w = tet_energy(geometry_[e], *material_, u_e, &f_e, nullptr);
    if (!std::isfinite(w)) return std::numeric_limits<double>::infinity();
    total += w;
    for (int a = 0; a < 4; ++a) f->segment<3>(3 * tets_(a, e)) += f_e.segment<3>(3 * a);
  }
  if (loads_) total += add_loads(u, f, nullptr);
  return total;
}

double Assembler::energy_force_tangent(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                                       std::vector<double>* k_values, bool project_psd) const {
  if (threads_ > 1) return energy_force_tangent_parallel(u, f, k_values, project_psd);
  f->setZero(pattern_.n);
  k_values->assign(pattern_.nnz(), 0.0);
  double total = 0;
  Vec12 u_e, f_e;
  Mat12 k_e;
  for (int e = 0; e < static_cast<int>(geometry_.size()); ++e) {
    gather(u, e, &u_e);
    const double w = tet_energy(geometry_[e], *material_, u_e, &f_e, &k_e);
    if (!std::isfinite(w)) return std::numeric_limits<double>::infinity();
    total += w;
    if (project_psd) project_to_psd(&k_e);
    std::array<double, 78> upper;
    upper_triangle(k_e, &upper);
    scatter(e, f_e, upper, f, k_values);
  }
  if (loads_) total += add_loads(u, f, k_values);
  return total;
}

// The element terms (the material law, the costly part) on threads_ OpenMP threads into
// per-element buffers, then the scatter in element order as in the serial loop: the sums, and so
// the results, are bitwise those of one thread.
double Assembler::energy_force_tangent_parallel(const Eigen::VectorXd& u, Eigen::VectorXd* f,
                                                std::vector<double>* k_values,
                                                bool project_psd) const {
  const int count = static_cast<int>(geometry_.size());
  element_w_.resize(count);
  element_f_.resize(count);
  element_k_.resize(count);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (int e = 0; e < count; ++e) {
    Vec12 u_e;
    gather(u, e, &u_e);
    Mat12 k_e;
    element_w_[e] = tet_energy(geometry_[e], *material_, u_e, &element_f_[e], &k_e);
    if (!std::isfinite(element_w_[e])) continue;  // k_e and f_e undefined: the sum is infinite
    if (project_psd) project_to_psd(&k_e);
    upper_triangle(k_e, &element_k_[e]);
  }
  f->setZero(pattern_.n);
  k_values->assign(pattern_.nnz(), 0.0);
  double total = 0;
  for (int e = 0; e < count; ++e) {
    if (!std::isfinite(element_w_[e])) return std::numeric_limits<double>::infinity();
    total += element_w_[e];
    scatter(e, element_f_[e], element_k_[e], f, k_values);
  }
  if (loads_) total += add_loads(u, f, k_values);
  return total;
}

}  // namespace hapstate
