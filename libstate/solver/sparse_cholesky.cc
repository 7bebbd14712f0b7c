#include "solver/sparse_cholesky.h"

#include <cholmod.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace hapstate {

struct SparseCholesky::Impl {
  cholmod_common common;
  cholmod_sparse matrix;  // views pattern arrays and `values`
  cholmod_factor* factor = nullptr;
  std::vector<int> col_ptr, row_idx;
  std::vector<double> values;
  cholmod_dense* rhs = nullptr;
  cholmod_dense* sol = nullptr;
  cholmod_dense* work_y = nullptr;
  cholmod_dense* work_e = nullptr;
};

SparseCholesky::SparseCholesky(const SymmetricPattern& pattern, Method method)
    : impl_(std::make_unique<Impl>()) {
  const auto start = std::chrono::steady_clock::now();
  Impl& s = *impl_;
  cholmod_start(&s.common);
  s.common.print = 0;
  s.common.error_handler = nullptr;
  s.common.quick_return_if_not_posdef = 1;
  // LL^T also in the simplicial method (its default LDL^T would accept an indefinite tangent and
  // Newton would then head for saddle points); indefiniteness must reach the PSD fallback.
  s.common.final_ll = 1;
  if (method == Method::kSimplicial) s.common.supernodal = CHOLMOD_SIMPLICIAL;
  if (method == Method::kSupernodal) s.common.supernodal = CHOLMOD_SUPERNODAL;
  s.col_ptr = pattern.col_ptr;
  s.row_idx = pattern.row_idx;
  s.values.assign(pattern.nnz(), 0.0);
  for (int c = 0; c < pattern.n; ++c) s.values[pattern.diag[c]] = 1.0;
  std::memset(&s.matrix, 0, sizeof(s.matrix));
  s.matrix.nrow = s.matrix.ncol = pattern.n;
  s.matrix.nzmax = pattern.nnz();
  s.matrix.p = s.col_ptr.data();
  s.matrix.i = s.row_idx.data();
  s.matrix.x = s.values.data();
  s.matrix.stype = 1;  // upper triangle stored
  s.matrix.itype = CHOLMOD_INT;
  s.matrix.xtype = CHOLMOD_REAL;
  s.matrix.dtype = CHOLMOD_DOUBLE;
  s.matrix.sorted = 1;
  s.matrix.packed = 1;
  s.factor = cholmod_analyze(&s.matrix, &s.common);
  if (s.factor == nullptr) {
    cholmod_finish(&s.common);
    throw std::runtime_error("CHOLMOD symbolic analysis failed (status " +
                             std::to_string(s.common.status) + ")");
  }
  s.rhs = cholmod_zeros(pattern.n, 1, CHOLMOD_REAL, &s.common);
  analyze_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SparseCholesky::~SparseCholesky() {
  Impl& s = *impl_;
  cholmod_free_dense(&s.rhs, &s.common);
  cholmod_free_dense(&s.sol, &s.common);
  cholmod_free_dense(&s.work_y, &s.common);
  cholmod_free_dense(&s.work_e, &s.common);
  cholmod_free_factor(&s.factor, &s.common);
  cholmod_finish(&s.common);
}

bool SparseCholesky::factorize(const std::vector<double>& values) {
  Impl& s = *impl_;
  std::copy(values.begin(), values.end(), s.values.begin());
  const int ok = cholmod_factorize(&s.matrix, s.factor, &s.common);
  return ok && s.common.status == CHOLMOD_OK && s.factor->minor == s.factor->n;
}

void SparseCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  Impl& s = *impl_;
  std::memcpy(s.rhs->x, b.data(), sizeof(double) * b.size());
  cholmod_solve2(CHOLMOD_A, s.factor, s.rhs, nullptr, &s.sol, nullptr, &s.work_y, &s.work_e,
                 &s.common);
  x->resize(b.size());
  std::memcpy(x->data(), s.sol->x, sizeof(double) * b.size());
}

}  // namespace hapstate

namespace hapstate {

double SparseCholesky::factor_nonzeros() const { return impl_->common.lnz; }
double SparseCholesky::factor_flops() const { return impl_->common.fl; }
double SparseCholesky::factor_bytes() const {
  const cholmod_factor* f = impl_->factor;
  if (f->is_super)
    return static_cast<double>(f->xsize) * sizeof(double) +
           static_cast<double>(f->ssize) * sizeof(int);
  return impl_->common.lnz * (sizeof(double) + sizeof(int));
}
const char* SparseCholesky::method() const {
  return impl_->factor->is_super ? "supernodal" : "simplicial";
}
const char* SparseCholesky::ordering() const {
  switch (impl_->factor->ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    case CHOLMOD_POSTORDERED:
      return "postordered";
  }
  return "unknown";
}

}  // namespace hapstate
