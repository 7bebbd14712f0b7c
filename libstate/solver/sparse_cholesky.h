// Sparse Cholesky factorisation (CHOLMOD) of a symmetric matrix with a fixed pattern: the
// symbolic analysis (fill-reducing ordering) is done once in the constructor and reused for
// every numeric factorisation. One instance per thread.
#pragma once

#include "fem/assembler.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace hapstate {

class SparseCholesky {
 public:
  enum class Method { kAuto, kSimplicial, kSupernodal };  // kAuto: CHOLMOD's own choice
  explicit SparseCholesky(const SymmetricPattern& pattern, Method method = Method::kAuto);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Numeric factorisation of the matrix with the given upper-triangle values (pattern order).
  // Returns false if the matrix is not positive definite (or the factorisation failed).
  bool factorize(const std::vector<double>& values);
  // x = A^{-1} b with the last successful factorisation.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd* x);
  // x ~ A^{-1} b with the factor rounded to single precision (a preconditioner: it reads half
  // the bytes of solve(), and conjugate gradients in double precision make up the difference).
  // A supernodal factor only; a simplicial one is solved in double precision. The rounded copy
  // is made on the first call after each factorisation.
  void solve_single(const Eigen::VectorXd& b, Eigen::VectorXd* x);

  double analyze_seconds() const { return analyze_seconds_; }
  // Non-zeros of the factor and flop count of one numeric factorisation (from the analysis).
  double factor_nonzeros() const;
  double factor_flops() const;
  // Bytes of the factor's values and row indices as stored (a supernodal factor stores its
  // supernodes' dense blocks): what one forward or one backward substitution reads; single:
  // what solve_single's substitutions read (the values as float; a simplicial factor's are
  // read as they are).
  double factor_bytes(bool single = false) const;
  // "supernodal" or "simplicial", and the fill-reducing ordering CHOLMOD chose.
  const char* method() const;
  const char* ordering() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double analyze_seconds_ = 0;
};

}  // namespace hapstate
