#include "d2vdb/fit/detail/SupernodalCholesky.h"

#include <Eigen/CholmodSupport>

#include <mutex>

namespace d2vdb::detail {

namespace {

/// Serialises every call into CHOLMOD (and so into its BLAS).
std::mutex& cholmodMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

struct SupernodalCholesky::Factor {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
  bool analyzed = false;
  bool factorized = false;
};

SupernodalCholesky::SupernodalCholesky() {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  factor_ = std::make_unique<Factor>();
  factor_->solver.cholmod().print = 0;  // failures are return values, not messages on stdout
}

SupernodalCholesky::~SupernodalCholesky() {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  factor_.reset();
}

void SupernodalCholesky::analyzePattern(const Eigen::SparseMatrix<double>& matrix) {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  factor_->solver.analyzePattern(matrix);
  factor_->analyzed = factor_->solver.info() == Eigen::Success;
  factor_->factorized = false;
}

bool SupernodalCholesky::factorize(const Eigen::SparseMatrix<double>& matrix) {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  factor_->factorized = false;
  if (!factor_->analyzed) return false;
  factor_->solver.factorize(matrix);
  factor_->factorized = factor_->solver.info() == Eigen::Success;
  return factor_->factorized;
}

Eigen::VectorXd SupernodalCholesky::solve(const Eigen::VectorXd& right) const {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  return factor_->solver.solve(right);
}

}  // namespace d2vdb::detail
