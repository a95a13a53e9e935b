#include "d2vdb/fit/QuadraticModel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
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
  patternStart_.clear();  // the next solve rebuilds the pattern with the regulariser's
  patternRows_.clear();
}

std::vector<Eigen::Vector3d> QuadraticModel::solve(
    const SensorMap& basis, const std::vector<QuadraticForm>& forms,
    const std::vector<Eigen::Vector3d>& controlPoints, double damping) {
  const int d = dimension_;
  const int order = basis.order();
  const int blockSize = order * d;
  const int unknowns = controlPointCount_ * d;
  const std::vector<int>& spanOrder = basis.spanOrder();
  const std::vector<int>& spanBegin = basis.spanBegin();
  const int groups = static_cast<int>(spanBegin.size()) - 1;
  const double inverseCount = forms.empty() ? 0.0 : 1.0 / static_cast<double>(forms.size());

  // Where each group's (a, b) block goes: the rank of control point a's row in b's column of the
  // pattern (false when a pair lies outside the stored pattern).
  std::vector<int> ranks(static_cast<std::size_t>(std::max(groups, 0) * order * order));
  const auto findRanks = [&](int g) {
    const int k = spanOrder[static_cast<std::size_t>(spanBegin[static_cast<std::size_t>(g)])];
    bool found = true;
    for (int a = 0; a < order; ++a) {
      for (int b = 0; b < order; ++b) {
        const int rank = patternRank(basis.index(k, a), basis.index(k, b));
        found = found && rank >= 0;
        ranks[static_cast<std::size_t>((g * order + a) * order + b)] = rank;
      }
    }
    return found;
  };

  // Per span group: a dense block over its p + 1 control points (its upper block triangle summed
  // sensor by sensor, then mirrored: the forms are symmetric) and the right-hand side.
  std::vector<Eigen::MatrixXd> blocks(static_cast<std::size_t>(std::max(groups, 0)));
  std::vector<Eigen::VectorXd> rhs(blocks.size());
  std::atomic<bool> outsidePattern{false};
  tbb::parallel_for(tbb::blocked_range<int>(0, std::max(groups, 0), 1),
                    [&](const tbb::blocked_range<int>& range) {
                      Eigen::VectorXd w(order);
                      for (int g = range.begin(); g != range.end(); ++g) {
                        if (!findRanks(g)) outsidePattern = true;
                        Eigen::MatrixXd block = Eigen::MatrixXd::Zero(blockSize, blockSize);
                        Eigen::VectorXd vector = Eigen::VectorXd::Zero(blockSize);
                        double* const entries = block.data();  // column-major
                        for (int i = spanBegin[static_cast<std::size_t>(g)];
                             i < spanBegin[static_cast<std::size_t>(g) + 1]; ++i) {
                          const int k = spanOrder[static_cast<std::size_t>(i)];
                          const QuadraticForm& form = forms[static_cast<std::size_t>(k)];
                          for (int a = 0; a < order; ++a) w[a] = basis.weight(k, a);
                          for (int b = 0; b < order; ++b) {
                            for (int r = 0; r < d; ++r) vector[b * d + r] += w[b] * form.b[r];
                            for (int a = 0; a <= b; ++a) {
                              const double wab = w[a] * w[b];
                              for (int c = 0; c < d; ++c) {
                                double* const column = entries + (b * d + c) * blockSize + a * d;
                                for (int r = 0; r < d; ++r) column[r] += wab * form.A(r, c);
                              }
                            }
                          }
                        }
                        for (int column = 0; column < blockSize; ++column) {
                          for (int row = column + 1; row < blockSize; ++row) {
                            block(row, column) = block(column, row);
                          }
                        }
                        blocks[static_cast<std::size_t>(g)] = inverseCount * block;
                        rhs[static_cast<std::size_t>(g)] = inverseCount * vector;
                      }
                    });
  if (outsidePattern || patternStart_.empty()) {  // new sensor spans (or none yet): rebuild
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(ranks.size());
    for (int g = 0; g < groups; ++g) {
      const int k = spanOrder[static_cast<std::size_t>(spanBegin[static_cast<std::size_t>(g)])];
      for (int a = 0; a < order; ++a) {
        for (int b = 0; b < order; ++b) pairs.emplace_back(basis.index(k, a), basis.index(k, b));
      }
    }
    rebuildPattern(pairs);
    for (int g = 0; g < groups; ++g) findRanks(g);
  }

  // Scatter in a fixed order (groups, then smoothing), so every entry sums the same way.
  double* const values = system_.valuePtr();
  std::fill(values, values + system_.nonZeros(), 0.0);
  Eigen::VectorXd right = Eigen::VectorXd::Zero(unknowns);
  for (int g = 0; g < groups; ++g) {
    const int k = spanOrder[static_cast<std::size_t>(spanBegin[static_cast<std::size_t>(g)])];
    const Eigen::MatrixXd& block = blocks[static_cast<std::size_t>(g)];
    for (int a = 0; a < order; ++a) {
      right.segment(basis.index(k, a) * d, d) += rhs[static_cast<std::size_t>(g)].segment(a * d, d);
      for (int b = 0; b < order; ++b) {
        const int column = basis.index(k, b);
        const int rank = ranks[static_cast<std::size_t>((g * order + a) * order + b)];
        for (int c = 0; c < d; ++c) {
          for (int r = 0; r < d; ++r) {
            values[valueIndex(rank, column, r, c)] += block(a * d + r, b * d + c);
          }
        }
      }
    }
  }
  addScaled(smoothing_, smoothingIndices_, 1.0);

  Eigen::VectorXd current(unknowns);
  for (int i = 0; i < controlPointCount_; ++i) {
    current.segment(i * d, d) = controlPoints[static_cast<std::size_t>(i)].head(d);
  }
  // Gradient condition of m at c: (H + mu m0 I) c = r - H P.
  const Eigen::VectorXd residual = right - system_ * current;
  double diagonalSum = 0.0;
  for (const int index : diagonalIndices_) diagonalSum += values[index];
  const double meanDiagonal = unknowns > 0 ? diagonalSum / unknowns : 0.0;
  const double ridge = (1e-12 + std::max(damping, 0.0)) * (meanDiagonal > 0.0 ? meanDiagonal : 1.0);
  for (const int index : diagonalIndices_) values[index] += ridge;
  if (regularizerWeight_ > 0.0 && regularizer_.nonZeros() > 0) {
    const double g0 = regularizer_.diagonal().mean();
    if (g0 > 0.0) {
      addScaled(regularizer_, regularizerIndices_,
                regularizerWeight_ * (meanDiagonal > 0.0 ? meanDiagonal : 1.0) / g0);
    }
  }
  if (!analyzed_) {
    solver_.analyzePattern(system_);
    analyzed_ = true;
  }
  solver_.factorize(system_);
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

int QuadraticModel::patternRank(int row, int column) const {
  if (patternStart_.empty()) return -1;
  const auto begin = patternRows_.begin() + patternStart_[static_cast<std::size_t>(column)];
  const auto end = patternRows_.begin() + patternStart_[static_cast<std::size_t>(column) + 1];
  const auto found = std::lower_bound(begin, end, row);
  return found != end && *found == row ? static_cast<int>(found - begin) : -1;
}

void QuadraticModel::rebuildPattern(const std::vector<std::pair<int, int>>& pairs) {
  const int n = controlPointCount_;
  const int d = dimension_;
  std::vector<std::vector<int>> columns(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    std::vector<int>& rows = columns[static_cast<std::size_t>(j)];
    rows.push_back(j);  // the ridge
    if (!patternStart_.empty()) {
      rows.insert(rows.end(), patternRows_.begin() + patternStart_[static_cast<std::size_t>(j)],
                  patternRows_.begin() + patternStart_[static_cast<std::size_t>(j) + 1]);
    }
  }
  for (const auto& [row, column] : pairs) columns[static_cast<std::size_t>(column)].push_back(row);
  for (const Eigen::SparseMatrix<double>* matrix : {&smoothing_, &regularizer_}) {
    for (int outer = 0; outer < matrix->outerSize(); ++outer) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(*matrix, outer); it; ++it) {
        columns[static_cast<std::size_t>(it.col())].push_back(static_cast<int>(it.row()));
      }
    }
  }
  patternStart_.assign(1, 0);
  patternRows_.clear();
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < n; ++j) {
    std::vector<int>& rows = columns[static_cast<std::size_t>(j)];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    patternRows_.insert(patternRows_.end(), rows.begin(), rows.end());
    patternStart_.push_back(static_cast<int>(patternRows_.size()));
    for (const int i : rows) {
      for (int c = 0; c < d; ++c) {
        for (int r = 0; r < d; ++r) entries.emplace_back(i * d + r, j * d + c, 0.0);
      }
    }
  }
  // Explicit zeros are kept: the stored pattern is the whole union, rows sorted per column, so
  // entry (i d + r, j d + c) sits at rank(i in j) * d + r within its column (valueIndex()).
  system_.resize(n * d, n * d);
  system_.setFromTriplets(entries.begin(), entries.end());
  system_.makeCompressed();
  smoothingIndices_ = valueIndicesOf(smoothing_);
  regularizerIndices_ = valueIndicesOf(regularizer_);
  diagonalIndices_.clear();
  for (int j = 0; j < n; ++j) {
    for (int a = 0; a < d; ++a) diagonalIndices_.push_back(valueIndex(patternRank(j, j), j, a, a));
  }
  analyzed_ = false;
}

std::vector<int> QuadraticModel::valueIndicesOf(const Eigen::SparseMatrix<double>& matrix) const {
  std::vector<int> indices;
  indices.reserve(static_cast<std::size_t>(matrix.nonZeros() * dimension_));
  for (int outer = 0; outer < matrix.outerSize(); ++outer) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, outer); it; ++it) {
      const int rank = patternRank(static_cast<int>(it.row()), static_cast<int>(it.col()));
      for (int a = 0; a < dimension_; ++a) {
        indices.push_back(valueIndex(rank, static_cast<int>(it.col()), a, a));
      }
    }
  }
  return indices;
}

void QuadraticModel::addScaled(const Eigen::SparseMatrix<double>& matrix,
                               const std::vector<int>& indices, double scale) {
  double* const values = system_.valuePtr();
  std::size_t e = 0;
  for (int outer = 0; outer < matrix.outerSize(); ++outer) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, outer); it; ++it, ++e) {
      for (int a = 0; a < dimension_; ++a) {
        values[indices[e * static_cast<std::size_t>(dimension_) + static_cast<std::size_t>(a)]] +=
            scale * it.value();
      }
    }
  }
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
