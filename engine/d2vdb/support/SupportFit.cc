#include "d2vdb/support/SupportFit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/support/detail/HarmonicKernels.h"
#include "d2vdb/support/detail/SupportDesign.h"

namespace d2vdb {
namespace {

// Samples per block of the Gram accumulation (rows of one rank update).
constexpr std::size_t kFitBlock = 256;
// The reduction tree has at most this many leaves (a function of the sample count only, so the
// summation order never depends on the thread count).
constexpr std::size_t kMaxLeaves = 16;

// Accumulates A = sum_i Y_i Y_i^T (lower triangle) and Z = sum_i Y_i v_i^T with v_i = (X_i . n_i,
// tangential part of X_i) over blocks of samples.
class GramAccumulator {
 public:
  GramAccumulator(const OrientedSamples& samples, int degree)
      : samples_(samples),
        degree_(degree),
        gram_(Eigen::MatrixXd::Zero(harmonicCount(degree), harmonicCount(degree))),
        moments_(Eigen::MatrixXd::Zero(harmonicCount(degree), 4)) {}
  GramAccumulator(GramAccumulator& other, tbb::split)
      : samples_(other.samples_),
        degree_(other.degree_),
        gram_(Eigen::MatrixXd::Zero(other.gram_.rows(), other.gram_.cols())),
        moments_(Eigen::MatrixXd::Zero(other.moments_.rows(), 4)) {}

  void operator()(const tbb::blocked_range<std::size_t>& blocks) {
    const int count = harmonicCount(degree_);
    Eigen::MatrixXd basis(static_cast<Eigen::Index>(kFitBlock), count);
    Eigen::MatrixXd values(static_cast<Eigen::Index>(kFitBlock), 4);
    double x[kFitBlock], y[kFitBlock], z[kFitBlock];
    const std::size_t total = samples_.points.size();
    for (std::size_t block = blocks.begin(); block != blocks.end(); ++block) {
      const std::size_t begin = block * kFitBlock;
      const std::size_t rows = std::min(kFitBlock, total - begin);
      for (std::size_t r = 0; r < rows; ++r) {
        const Eigen::Vector3d& n = samples_.normals[begin + r];
        const Eigen::Vector3d& p = samples_.points[begin + r];
        x[r] = n.x();
        y[r] = n.y();
        z[r] = n.z();
        const double h = p.dot(n);
        const Eigen::Vector3d tangential = p - h * n;
        const auto row = static_cast<Eigen::Index>(r);
        values(row, 0) = h;
        values(row, 1) = tangential.x();
        values(row, 2) = tangential.y();
        values(row, 3) = tangential.z();
      }
      const auto n = static_cast<Eigen::Index>(rows);
      detail::evaluateHarmonicBlock(degree_, static_cast<int>(rows), x, y, z, basis.data(),
                                    static_cast<int>(kFitBlock));
      gram_.selfadjointView<Eigen::Lower>().rankUpdate(basis.topRows(n).transpose());
      moments_.noalias() += basis.topRows(n).transpose() * values.topRows(n);
    }
  }

  void join(const GramAccumulator& other) {
    gram_.triangularView<Eigen::Lower>() += other.gram_;
    moments_ += other.moments_;
  }

  Eigen::MatrixXd& gram() { return gram_; }
  const Eigen::MatrixXd& moments() const { return moments_; }

 private:
  const OrientedSamples& samples_;
  int degree_;
  Eigen::MatrixXd gram_;
  Eigen::MatrixXd moments_;
};

}  // namespace

namespace detail {

Eigen::MatrixXd supportDesignMatrix(const std::vector<Eigen::Vector3d>& unitNormals, int degree) {
  const int count = harmonicCount(degree);
  const int lower = harmonicCount(degree - 1);
  Eigen::SparseMatrix<double> partial[3];
  for (int axis = 0; axis < 3; ++axis) partial[axis] = partialDerivativeMatrix(degree, axis);
  Eigen::MatrixXd design(3 * static_cast<Eigen::Index>(unitNormals.size()), count);
  Eigen::VectorXd lDegree(count);
  for (int j = 0; j < count; ++j) lDegree[j] = harmonicDegreeOf(j);
  for (std::size_t i = 0; i < unitNormals.size(); ++i) {
    const Eigen::Vector3d& n = unitNormals[i];
    const Eigen::VectorXd y = evaluateHarmonics(degree, n);
    const Eigen::VectorXd radial = (1.0 - lDegree.array()) * y.array();
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::VectorXd row = n[axis] * radial;
      if (lower > 0) row += partial[axis].transpose() * y.head(lower);
      design.row(3 * static_cast<Eigen::Index>(i) + axis) = row.transpose();
    }
  }
  return design;
}

}  // namespace detail

SupportFunction fitSupportFunction(OrientedSamples samples, const SupportFitOptions& options,
                                   SupportFitReport* report, const std::string& sourceName) {
  const int degree = options.degree;
  if (degree < 0 || degree > kMaxSupportDegree) {
    throw InputError("support function degree " + std::to_string(degree) +
                     " is not supported (expected 0 to " + std::to_string(kMaxSupportDegree) + ")");
  }
  if (!(options.regularization >= 0.0) || !std::isfinite(options.regularization)) {
    throw InputError("the regularisation weight must be a finite number >= 0");
  }
  const SampleCheck check = checkOrientedSamples(samples, sourceName);
  const int count = harmonicCount(degree);
  const std::size_t total = samples.points.size();
  if (total < static_cast<std::size_t>(count)) {
    throw InputError(sourceName + ": " + std::to_string(total) + " samples are fewer than the " +
                     std::to_string(count) + " unknowns of a degree-" + std::to_string(degree) +
                     " support function; give more samples or a lower degree");
  }

  // Gram matrix of the harmonic values and the right-hand-side moments.
  const std::size_t blocks = (total + kFitBlock - 1) / kFitBlock;
  const std::size_t grain = std::max<std::size_t>(1, (blocks + kMaxLeaves - 1) / kMaxLeaves);
  GramAccumulator accumulator(samples, degree);
  tbb::parallel_deterministic_reduce(tbb::blocked_range<std::size_t>(0, blocks, grain),
                                     accumulator);
  Eigen::MatrixXd& gram = accumulator.gram();
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  const Eigen::MatrixXd& moments = accumulator.moments();

  // Normal matrix G = A + sum_k D_k^T A' D_k - Lambda A Lambda, right-hand side
  // b = Z_0 + sum_k D_k^T Z'_k (see SupportFit.h).
  const int lower = harmonicCount(degree - 1);
  Eigen::VectorXd lDegree(count);
  for (int j = 0; j < count; ++j) lDegree[j] = detail::harmonicDegreeOf(j);
  Eigen::MatrixXd normal = gram;
  normal.array() -= (lDegree * lDegree.transpose()).array() * gram.array();
  Eigen::VectorXd rhs = moments.col(0);
  if (lower > 0) {
    const Eigen::MatrixXd lowerGram = gram.topLeftCorner(lower, lower);
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::SparseMatrix<double> partial = detail::partialDerivativeMatrix(degree, axis);
      const Eigen::MatrixXd right = lowerGram * partial;
      normal.noalias() += partial.transpose() * right;
      rhs.noalias() += partial.transpose() * moments.col(axis + 1).head(lower);
    }
  }
  const double penaltyScale = options.regularization * static_cast<double>(total) / (4.0 * kPi);
  for (int j = 0; j < count; ++j) {
    const double l = lDegree[j];
    normal(j, j) += penaltyScale * (l - 1.0) * l * (l + 1.0) * (l + 2.0);
  }

  // Jacobi scaling, Cholesky.
  Eigen::VectorXd scale(count);
  for (int j = 0; j < count; ++j) {
    const double diagonal = normal(j, j);
    if (!(diagonal > 0.0) || !std::isfinite(diagonal)) {
      throw InputError(sourceName + ": the samples do not determine harmonic " + std::to_string(j) +
                       " of the degree-" + std::to_string(degree) +
                       " support function (its column of the normal matrix is zero)");
    }
    scale[j] = 1.0 / std::sqrt(diagonal);
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * normal * scale.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> cholesky(scaled);
  const double rcond = cholesky.info() == Eigen::Success ? cholesky.rcond() : 0.0;
  if (!(rcond > 1e-15)) {
    throw InputError(sourceName + ": the samples' normals do not determine a degree-" +
                     std::to_string(degree) +
                     " support function (the least-squares system is singular to working "
                     "precision); lower the degree, sample more directions, or raise the "
                     "regularisation");
  }
  const Eigen::VectorXd coefficients =
      scale.asDiagonal() * cholesky.solve(scale.asDiagonal() * rhs);
  SupportFunction fitted(degree, coefficients);

  if (report != nullptr) {
    const std::vector<Eigen::Vector3d> fittedPoints = fitted.points(samples.normals);
    SupportFitReport r;
    r.samples = total;
    r.degree = degree;
    r.unknowns = count;
    r.regularization = options.regularization;
    double sum = 0.0;
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i < total; ++i) {
      const double residual = (samples.points[i] - fittedPoints[i]).norm();
      sum += residual * residual;
      if (residual > r.maxResidual) {
        r.maxResidual = residual;
        r.worstSample = i;
      }
      box.extend(samples.points[i]);
    }
    r.rmsResidual = std::sqrt(sum / static_cast<double>(total));
    r.size = box.diagonal().norm();
    r.reciprocalCondition = rcond;
    r.renormalizedNormals = check.renormalized;
    r.largestNormalDeviation = check.largestDeviation;
    *report = r;
  }
  return fitted;
}

}  // namespace d2vdb
