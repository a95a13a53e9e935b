#include "d2vdb/fit/detail/SupernodalCholesky.h"

#include <dlfcn.h>

#include <Eigen/CholmodSupport>

#include <mutex>

namespace d2vdb::detail {

namespace {

/// Serialises every call into CHOLMOD (and so into its BLAS).
std::mutex& cholmodMutex() {
  static std::mutex mutex;
  return mutex;
}

/// While alive, keeps OpenMP parallel regions on their calling thread. CHOLMOD (Debian's build)
/// runs some of its loops on a team of CHOLMOD_OMP_NUM_THREADS = 4 OpenMP threads, whatever the
/// machine and the TBB limit: threads beside TBB's workers that take cores from d2vdb's parallel
/// work, spin after each loop, and make a one-thread run use several. The factorisations are
/// serial by design here (one BLAS thread, deterministic). A fixed num_threads clause overrides
/// omp_set_num_threads(), so the scope sets the maximum number of active parallel levels to 0
/// (every region then runs on one thread) and restores it afterwards. That setting is global to
/// the process: held only for the duration of a CHOLMOD call, under the mutex that serialises
/// them. The functions are looked up in the OpenMP runtime that CHOLMOD loaded (none: nothing to
/// do).
class SerialOpenMpScope {
 public:
  SerialOpenMpScope() {
    if (runtime().set != nullptr && runtime().get != nullptr) {
      saved_ = runtime().get();
      runtime().set(0);
    }
  }
  ~SerialOpenMpScope() {
    if (saved_ >= 0) runtime().set(saved_);
  }
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  struct Runtime {
    void (*set)(int) = nullptr;
    int (*get)() = nullptr;
  };
  static const Runtime& runtime() {
    static const Runtime functions{
        reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels")),
        reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"))};
    return functions;
  }
  int saved_ = -1;
};

}  // namespace

// The upper triangle: CHOLMOD's supernodal factorisation then transposes the permuted matrix once
// instead of twice (the lower triangle costs one more transpose per factorisation).
struct SupernodalCholesky::Factor {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> solver;
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
  const SerialOpenMpScope serial;
  factor_->solver.analyzePattern(matrix);
  factor_->analyzed = factor_->solver.info() == Eigen::Success;
  factor_->factorized = false;
}

bool SupernodalCholesky::factorize(const Eigen::SparseMatrix<double>& matrix) {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  factor_->factorized = false;
  if (!factor_->analyzed) return false;
  const SerialOpenMpScope serial;
  factor_->solver.factorize(matrix);
  factor_->factorized = factor_->solver.info() == Eigen::Success;
  return factor_->factorized;
}

Eigen::VectorXd SupernodalCholesky::solve(const Eigen::VectorXd& right) const {
  const std::lock_guard<std::mutex> lock(cholmodMutex());
  const SerialOpenMpScope serial;
  return factor_->solver.solve(right);
}

}  // namespace d2vdb::detail
