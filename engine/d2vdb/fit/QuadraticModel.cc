#include "d2vdb/fit/QuadraticModel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {

QuadraticModel::QuadraticModel(int controlPointCount, int dimension,
                               Eigen::SparseMatrix<double> smoothing)
    : controlPointCount_(controlPointCount),
      dimension_(dimension),
      smoothing_(std::move(smoothing)) {
  if (dimension != 2 && dimension != 3) {
    throw InputError("fitting dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  if (smoothing_.rows() != controlPointCount || smoothing_.cols() != controlPointCount) {
    throw InputError("smoothing matrix is " + std::to_string(smoothing_.rows()) + " x " +
                     std::to_string(smoothing_.cols()) + ", expected " +
                     std::to_string(controlPointCount) + " square");
  }
}

void QuadraticModel::setStepRegularizer(Eigen::SparseMatrix<double> regularizer, double rho) {
  if (regularizer.rows() != controlPointCount_ || regularizer.cols() != controlPointCount_) {
    throw InputError("step regulariser has the wrong size");
  }
  if (!(rho >= 0.0) || !std::isfinite(rho)) {
    throw InputError("the step regulariser weight must be finite and non-negative");
  }
  regularizer_ = std::move(regularizer);
  regularizerWeight_ = rho;
}

std::vector<Eigen::Vector3d> QuadraticModel::solve(
    const SensorBasis& basis, const std::vector<QuadraticForm>& forms,
    const std::vector<Eigen::Vector3d>& controlPoints, double damping) {
  const int d = dimension_;
  const int order = basis.order();
  const int blockSize = order * d;
  const int unknowns = controlPointCount_ * d;
  const std::vector<int>& spanOrder = basis.spanOrder();
  const std::vector<int>& spanBegin = basis.spanBegin();
  const int groups = static_cast<int>(spanBegin.size()) - 1;
  const double inverseCount = forms.empty() ? 0.0 : 1.0 / static_cast<double>(forms.size());

  // Per span group: a dense block over its p + 1 control points and the right-hand side.
  std::vector<Eigen::MatrixXd> blocks(static_cast<std::size_t>(std::max(groups, 0)));
  std::vector<Eigen::VectorXd> rhs(blocks.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, std::max(groups, 0), 1),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int g = range.begin(); g != range.end(); ++g) {
                        Eigen::MatrixXd block = Eigen::MatrixXd::Zero(blockSize, blockSize);
                        Eigen::VectorXd vector = Eigen::VectorXd::Zero(blockSize);
                        for (int i = spanBegin[static_cast<std::size_t>(g)];
                             i < spanBegin[static_cast<std::size_t>(g) + 1]; ++i) {
                          const int k = spanOrder[static_cast<std::size_t>(i)];
                          const QuadraticForm& form = forms[static_cast<std::size_t>(k)];
                          for (int a = 0; a < order; ++a) {
                            const double wa = basis.weight(k, a);
                            vector.segment(a * d, d) += wa * form.b.head(d);
                            for (int b = 0; b < order; ++b) {
                              block.block(a * d, b * d, d, d) +=
                                  (wa * basis.weight(k, b)) * form.A.topLeftCorner(d, d);
                            }
                          }
                        }
                        blocks[static_cast<std::size_t>(g)] = inverseCount * block;
                        rhs[static_cast<std::size_t>(g)] = inverseCount * vector;
                      }
                    });

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(blocks.size() * static_cast<std::size_t>(blockSize * blockSize) +
                   static_cast<std::size_t>(smoothing_.nonZeros() * d + unknowns));
  Eigen::VectorXd right = Eigen::VectorXd::Zero(unknowns);
  for (int g = 0; g < groups; ++g) {
    const int k = spanOrder[static_cast<std::size_t>(spanBegin[static_cast<std::size_t>(g)])];
    const Eigen::MatrixXd& block = blocks[static_cast<std::size_t>(g)];
    for (int a = 0; a < order; ++a) {
      const int row = basis.index(k, a) * d;
      right.segment(row, d) += rhs[static_cast<std::size_t>(g)].segment(a * d, d);
      for (int b = 0; b < order; ++b) {
        const int col = basis.index(k, b) * d;
        for (int r = 0; r < d; ++r) {
          for (int c = 0; c < d; ++c) {
            const double value = block(a * d + r, b * d + c);
            if (value != 0.0) triplets.emplace_back(row + r, col + c, value);
          }
        }
      }
    }
  }
  for (int outer = 0; outer < smoothing_.outerSize(); ++outer) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(smoothing_, outer); it; ++it) {
      for (int a = 0; a < d; ++a) {
        triplets.emplace_back(static_cast<int>(it.row()) * d + a,
                              static_cast<int>(it.col()) * d + a, it.value());
      }
    }
  }
  Eigen::SparseMatrix<double> system(unknowns, unknowns);
  system.setFromTriplets(triplets.begin(), triplets.end());

  Eigen::VectorXd current(unknowns);
  for (int i = 0; i < controlPointCount_; ++i) {
    current.segment(i * d, d) = controlPoints[static_cast<std::size_t>(i)].head(d);
  }
  // Gradient condition of m at c: (H + mu m0 I) c = r - H P.
  const Eigen::VectorXd residual = right - system * current;
  const double meanDiagonal = unknowns > 0 ? system.diagonal().mean() : 0.0;
  const double ridge = (1e-12 + std::max(damping, 0.0)) * (meanDiagonal > 0.0 ? meanDiagonal : 1.0);
  Eigen::SparseMatrix<double> identity(unknowns, unknowns);
  identity.setIdentity();
  system += ridge * identity;
  if (regularizerWeight_ > 0.0 && regularizer_.nonZeros() > 0) {
    const double g0 = regularizer_.diagonal().mean();
    if (g0 > 0.0) {
      const double weight = regularizerWeight_ * (meanDiagonal > 0.0 ? meanDiagonal : 1.0) / g0;
      std::vector<Eigen::Triplet<double>> extra;
      for (int outer = 0; outer < regularizer_.outerSize(); ++outer) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(regularizer_, outer); it; ++it) {
          for (int a = 0; a < d; ++a) {
            extra.emplace_back(static_cast<int>(it.row()) * d + a,
                               static_cast<int>(it.col()) * d + a, weight * it.value());
          }
        }
      }
      Eigen::SparseMatrix<double> added(unknowns, unknowns);
      added.setFromTriplets(extra.begin(), extra.end());
      system += added;
    }
  }
  solver_.compute(system);
  if (solver_.info() != Eigen::Success) {
    throw RuntimeFailure(
        "the fitting system could not be factorised (non-finite or indefinite "
        "quadratic forms)");
  }
  const Eigen::VectorXd step = solver_.solve(residual);
  if (solver_.info() != Eigen::Success || !step.allFinite()) {
    throw RuntimeFailure("the fitting system could not be solved (non-finite step)");
  }
  std::vector<Eigen::Vector3d> displacement(static_cast<std::size_t>(controlPointCount_),
                                            Eigen::Vector3d::Zero());
  for (int i = 0; i < controlPointCount_; ++i) {
    displacement[static_cast<std::size_t>(i)].head(d) = step.segment(i * d, d);
  }
  return displacement;
}

double QuadraticModel::smoothingEnergy(const std::vector<Eigen::Vector3d>& controlPoints) const {
  double energy = 0.0;
  for (int a = 0; a < dimension_; ++a) {
    Eigen::VectorXd coordinate(controlPointCount_);
    for (int i = 0; i < controlPointCount_; ++i) {
      coordinate[i] = controlPoints[static_cast<std::size_t>(i)][a];
    }
    energy += coordinate.dot(smoothing_ * coordinate);
  }
  return energy;
}

}  // namespace d2vdb
