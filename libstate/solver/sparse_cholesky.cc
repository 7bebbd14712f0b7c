#include "solver/sparse_cholesky.h"

#include "solver/serial_openmp.h"

#include <cholmod.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
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
  // solve_single: the supernodal factor's values rounded to float (current while
  // single_current), the permuted right-hand side and a supernode's gathered rows.
  std::vector<float> single_x, single_w, single_rows;
  bool single_current = false;
};

namespace {

// The symbolic analyses of this process, shared: every solver of a stage factorises the same
// pattern, and one analysis (the fill-reducing ordering: liverFine 0.17 s, more on bigger
// meshes) serves them all; each gets a copy. The most recent few patterns are kept.
struct Analysis {
  std::vector<int> col_ptr, row_idx;
  SparseCholesky::Method method;
  cholmod_common common;
  cholmod_factor* symbolic = nullptr;
  double lnz = 0, fl = 0;
  Analysis() { cholmod_start(&common); }
  ~Analysis() {
    cholmod_free_factor(&symbolic, &common);
    cholmod_finish(&common);
  }
  Analysis(const Analysis&) = delete;
  Analysis& operator=(const Analysis&) = delete;
};
constexpr std::size_t kKeptAnalyses = 4;

// The analysis of `matrix` (whose pattern col_ptr / row_idx are), copied from the cache or made
// and kept. One at a time: METIS (one of the orderings CHOLMOD tries) keeps its random state in
// globals, and two analyses at once on two threads raced on it and gave different orderings,
// so different factors, rounding and conjugate-gradient counts from one run to the next
// (liverFine: factors of 38.3-40.1 MB, 18-49 s for the same 26 transitions, catalogues that
// differed).
cholmod_factor* analyze(const std::vector<int>& col_ptr, const std::vector<int>& row_idx,
                        SparseCholesky::Method method, cholmod_sparse* matrix,
                        cholmod_common* common) {
  static std::mutex mutex;
  static std::vector<std::unique_ptr<Analysis>> kept;
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& a : kept) {
    if (a->method != method || a->col_ptr != col_ptr || a->row_idx != row_idx) continue;
    common->lnz = a->lnz;
    common->fl = a->fl;
    return cholmod_copy_factor(a->symbolic, common);
  }
  cholmod_factor* factor = cholmod_analyze(matrix, common);
  if (factor == nullptr) return nullptr;
  auto a = std::make_unique<Analysis>();
  a->col_ptr = col_ptr;
  a->row_idx = row_idx;
  a->method = method;
  a->lnz = common->lnz;
  a->fl = common->fl;
  a->symbolic = cholmod_copy_factor(factor, &a->common);
  if (a->symbolic != nullptr) {
    if (kept.size() == kKeptAnalyses) kept.erase(kept.begin());
    kept.push_back(std::move(a));
  }
  return factor;
}

}  // namespace

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
  s.factor = analyze(s.col_ptr, s.row_idx, method, &s.matrix, &s.common);
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
  s.single_current = false;
  const SerialOpenMP serial;  // the caller's thread is the parallelism (solver/serial_openmp.h)
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

// L L^T = P A P^T with L supernodal (CHOLMOD's layout: supernode j holds columns super[j] ..
// super[j+1]-1; its rows s[pi[j]] .. s[pi[j+1]-1], the first ones its own columns; its values a
// dense column-major block at x[px[j]] with one row per row index). x = P^T L^-T L^-1 P b.
void SparseCholesky::solve_single(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  Impl& s = *impl_;
  const cholmod_factor* f = s.factor;
  if (!f->is_super || f->itype != CHOLMOD_INT) {
    solve(b, x);
    return;
  }
  const auto n = static_cast<Eigen::Index>(f->n);
  if (!s.single_current) {
    const auto* values = static_cast<const double*>(f->x);
    s.single_x.resize(f->xsize);
    for (std::size_t k = 0; k < f->xsize; ++k) s.single_x[k] = static_cast<float>(values[k]);
    s.single_w.resize(f->n);
    s.single_rows.resize(std::max<std::size_t>(f->maxesize, 1));
    s.single_current = true;
  }
  const auto* perm = static_cast<const int*>(f->Perm);
  const auto* super = static_cast<const int*>(f->super);
  const auto* pi = static_cast<const int*>(f->pi);
  const auto* px = static_cast<const int*>(f->px);
  const auto* rows = static_cast<const int*>(f->s);
  float* w = s.single_w.data();
  float* gathered = s.single_rows.data();
  for (Eigen::Index k = 0; k < n; ++k) w[k] = static_cast<float>(b[perm[k]]);
  const auto nsuper = static_cast<int>(f->nsuper);
  using Block = Eigen::Map<const Eigen::MatrixXf>;
  for (int j = 0; j < nsuper; ++j) {  // forward: L y = P b
    const int first = super[j], cols = super[j + 1] - first;
    const int below = pi[j + 1] - pi[j] - cols;
    const Block block(s.single_x.data() + px[j], cols + below, cols);
    Eigen::Map<Eigen::VectorXf> y(w + first, cols);
    block.topRows(cols).triangularView<Eigen::Lower>().solveInPlace(y);
    if (below == 0) continue;
    Eigen::Map<Eigen::VectorXf> update(gathered, below);
    update.noalias() = block.bottomRows(below) * y;
    const int* below_rows = rows + pi[j] + cols;
    for (int r = 0; r < below; ++r) w[below_rows[r]] -= update[r];
  }
  for (int j = nsuper - 1; j >= 0; --j) {  // backward: L^T z = y
    const int first = super[j], cols = super[j + 1] - first;
    const int below = pi[j + 1] - pi[j] - cols;
    const Block block(s.single_x.data() + px[j], cols + below, cols);
    Eigen::Map<Eigen::VectorXf> z(w + first, cols);
    if (below > 0) {
      Eigen::Map<Eigen::VectorXf> known(gathered, below);
      const int* below_rows = rows + pi[j] + cols;
      for (int r = 0; r < below; ++r) known[r] = w[below_rows[r]];
      z.noalias() -= block.bottomRows(below).transpose() * known;
    }
    block.topRows(cols).triangularView<Eigen::Lower>().transpose().solveInPlace(z);
  }
  x->resize(n);
  for (Eigen::Index k = 0; k < n; ++k) (*x)[perm[k]] = w[k];
}

}  // namespace hapstate

namespace hapstate {

double SparseCholesky::factor_nonzeros() const { return impl_->common.lnz; }
double SparseCholesky::factor_flops() const { return impl_->common.fl; }
double SparseCholesky::factor_bytes(bool single) const {
  const cholmod_factor* f = impl_->factor;
  if (f->is_super)
    return static_cast<double>(f->xsize) * (single ? sizeof(float) : sizeof(double)) +
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
