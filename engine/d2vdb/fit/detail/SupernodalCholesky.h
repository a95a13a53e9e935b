// Sparse Cholesky factorisation by CHOLMOD's supernodal method, for the fitting systems.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>

namespace d2vdb::detail {

/// A = L L^T of a sparse symmetric positive definite matrix (only its upper triangle is read) by
/// the supernodal method of CHOLMOD (SuiteSparse; Y. Chen, T. A. Davis, W. W. Hager,
/// S. Rajamanickam, "Algorithm 887: CHOLMOD, supernodal sparse Cholesky factorization and
/// update/downdate", ACM TOMS 2008), whose dense kernels are BLAS level 3. The fill-reducing
/// ordering and the symbolic analysis of analyzePattern() are kept for every later factorize()
/// of a matrix with the same pattern. The factorisation is serial and deterministic; calls into
/// CHOLMOD are serialised process-wide (its BLAS need not be reentrant), so instances may live in
/// different threads. Nothing is printed: failures are reported by return values.
class SupernodalCholesky {
 public:
  SupernodalCholesky();
  ~SupernodalCholesky();
  SupernodalCholesky(const SupernodalCholesky&) = delete;
  SupernodalCholesky& operator=(const SupernodalCholesky&) = delete;

  /// Orders and analyses the pattern of `matrix` (square, compressed, column-major).
  void analyzePattern(const Eigen::SparseMatrix<double>& matrix);

  /// Factorises `matrix` (the pattern of the last analyzePattern()). False when it is not
  /// positive definite (the factorisation stopped at a non-positive pivot) or CHOLMOD failed;
  /// solve() must not be called then.
  bool factorize(const Eigen::SparseMatrix<double>& matrix);

  /// x with A x = right for the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& right) const;

 private:
  struct Factor;
  std::unique_ptr<Factor> factor_;
};

}  // namespace d2vdb::detail
