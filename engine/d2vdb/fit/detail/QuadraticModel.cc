#include "d2vdb/fit/detail/QuadraticModel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/SupernodalCholesky.h"

namespace d2vdb::detail {

namespace {

/// A smoothing matrix of the right size: an empty one becomes an n x n zero matrix.
Eigen::SparseMatrix<double> sized(Eigen::SparseMatrix<double> matrix, int n, const char* what) {
  if (matrix.rows() == 0 && matrix.cols() == 0) return Eigen::SparseMatrix<double>(n, n);
  if (matrix.rows() != n || matrix.cols() != n) {
    throw InputError(std::string(what) + " is " + std::to_string(matrix.rows()) + " x " +
                     std::to_string(matrix.cols()) + ", expected " + std::to_string(n) + " square");
  }
  matrix.makeCompressed();
  return matrix;
}

}  // namespace

QuadraticModel::QuadraticModel(int controlPointCount, int dimension,
                               Eigen::SparseMatrix<double> smoothing,
                               Eigen::SparseMatrix<double> scaledSmoothing)
    : controlPointCount_(controlPointCount), dimension_(dimension) {
  if (dimension != 2 && dimension != 3) {
    throw InputError("fitting dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  smoothing_ = sized(std::move(smoothing), controlPointCount, "smoothing matrix");
  scaledSmoothing_ = sized(std::move(scaledSmoothing), controlPointCount, "smoothing matrix");
}

QuadraticModel::~QuadraticModel() = default;

void QuadraticModel::setStepRegularizer(Eigen::SparseMatrix<double> regularizer, double rho) {
  if (regularizer.rows() != controlPointCount_ || regularizer.cols() != controlPointCount_) {
    throw InputError("step regulariser has the wrong size");
  }
  if (!(rho >= 0.0) || !std::isfinite(rho)) {
    throw InputError("the step regulariser weight must be finite and non-negative");
  }
  regularizer_ = std::move(regularizer);
  regularizerWeight_ = rho;
  patternStart_.clear();  // the next assembly rebuilds the pattern with the regulariser's
  patternRows_.clear();
  assembled_ = false;
}

void QuadraticModel::setSmoothingScale(double scale) {
  if (!(scale >= 0.0) || !std::isfinite(scale)) {
    throw InputError("the smoothing scale must be finite and non-negative");
  }
  smoothingScale_ = scale;
}

std::vector<Eigen::Vector3d> QuadraticModel::solve(
    const SensorMap& basis, const std::vector<QuadraticForm>& forms,
    const std::vector<Eigen::Vector3d>& controlPoints, double damping) {
  const double weight = forms.empty() ? 0.0 : 1.0 / static_cast<double>(forms.size());
  assemble({SensorTerms{&basis, &forms, weight, nullptr}}, controlPoints);
  return solveAssembled(1.0, damping);
}

void QuadraticModel::assemble(const std::vector<SensorTerms>& terms,
                              const std::vector<Eigen::Vector3d>& controlPoints) {
  const int d = dimension_;
  if (static_cast<int>(controlPoints.size()) != controlPointCount_) {
    throw InputError("the fitting model expects " + std::to_string(controlPointCount_) +
                     " control points, got " + std::to_string(controlPoints.size()));
  }
  // Every span group of every sensor set, in set order: (set, group).
  std::vector<std::pair<int, int>> groupList;
  for (std::size_t s = 0; s < terms.size(); ++s) {
    const SensorTerms& set = terms[s];
    if (set.basis == nullptr || set.forms == nullptr ||
        static_cast<int>(set.forms->size()) != set.basis->sensorCount() ||
        set.basis->controlPointCount() != controlPointCount_) {
      throw InputError("a sensor set of the fitting model does not match its basis or net");
    }
    if (set.rankOne != nullptr && !set.rankOne->empty() &&
        (set.rankOne->length != (set.rankOne->separable ? d : set.basis->order() * d) ||
         static_cast<int>(set.rankOne->start.size()) != set.basis->sensorCount() + 1 ||
         set.rankOne->vectors.size() !=
             set.rankOne->coefficients.size() * static_cast<std::size_t>(set.rankOne->length) ||
         set.rankOne->start.back() != static_cast<int>(set.rankOne->coefficients.size()))) {
      throw InputError("the rank-one terms of a sensor set do not match its basis");
    }
    const int groups = static_cast<int>(set.basis->spanBegin().size()) - 1;
    for (int g = 0; g < groups; ++g) groupList.emplace_back(static_cast<int>(s), g);
  }
  const int groups = static_cast<int>(groupList.size());
  const auto setOf = [&](int i) -> const SensorTerms& {
    return terms[static_cast<std::size_t>(groupList[static_cast<std::size_t>(i)].first)];
  };
  // The first sensor of group i (all of its sensors share their control points).
  const auto firstSensor = [&](int i) {
    const SensorMap& basis = *setOf(i).basis;
    return basis.spanOrder()[static_cast<std::size_t>(basis.spanBegin()[static_cast<std::size_t>(
        groupList[static_cast<std::size_t>(i)].second)])];
  };
  std::vector<int> rankStart(static_cast<std::size_t>(groups) + 1, 0);
  for (int i = 0; i < groups; ++i) {
    const int order = setOf(i).basis->order();
    rankStart[static_cast<std::size_t>(i) + 1] =
        rankStart[static_cast<std::size_t>(i)] + order * order;
  }

  // Where each group's (a, b) block goes: the rank of control point a's row in b's column of the
  // pattern (false when a pair lies outside the stored pattern).
  std::vector<int> ranks(static_cast<std::size_t>(rankStart.back()));
  const auto findRanks = [&](int i) {
    const SensorMap& basis = *setOf(i).basis;
    const int order = basis.order();
    const int k = firstSensor(i);
    bool found = true;
    for (int a = 0; a < order; ++a) {
      for (int b = 0; b < order; ++b) {
        const int rank = patternRank(basis.index(k, a), basis.index(k, b));
        found = found && rank >= 0;
        ranks[static_cast<std::size_t>(rankStart[static_cast<std::size_t>(i)] + a * order + b)] =
            rank;
      }
    }
    return found;
  };

  // Per span group: a dense block over its control points (its upper block triangle summed
  // sensor by sensor, then mirrored: the forms are symmetric) and the right-hand side; the same
  // for the rank-one terms.
  struct GroupSums {
    Eigen::MatrixXd block, rankOneBlock;
    Eigen::VectorXd right, rankOneRight;
  };
  std::vector<GroupSums> sums(static_cast<std::size_t>(groups));
  std::atomic<bool> outsidePattern{false};
  tbb::parallel_for(tbb::blocked_range<int>(0, groups, 1), [&](const tbb::blocked_range<int>&
                                                                   range) {
    Eigen::MatrixXd weights;  // sensors x order: each sensor's basis weights
    Eigen::MatrixXd entries;  // sensors x d(d+1)/2: each sensor's symmetric d x d matrix
    Eigen::MatrixXd rights;   // sensors x d: each sensor's right-hand side
    Eigen::MatrixXd scaledLow, scaledHigh, gramLow, gramHigh;
    Eigen::VectorXd local;
    std::vector<double> upper;  // the Gram values of one group, [(a * order + b) * E + e]
    // A knot cell whose sensors form a full grid of gridU x gridV (u, v) parameters of a
    // tensor-product map: gridRow[iu * gridV + iv] is the row in `weights` of the sensor at
    // (u_iu, v_iv), valuesU / valuesV the u and v basis values of the grid's lines.
    bool isGrid = false;
    int gridU = 0, gridV = 0;
    std::vector<int> gridRow, keysU, keysV, rowKeyU, rowKeyV;
    Eigen::MatrixXd valuesU, valuesV, pairsU, pairsV, partial, tensorGram;
    const auto detectGrid = [&](const SensorMap& basis, int first, int last) {
      isGrid = false;
      const int orderU = basis.orderU();
      if (orderU <= 0) return;
      const int orderV = basis.order() / orderU;
      const int count = last - first;
      rowKeyU.resize(static_cast<std::size_t>(count));
      rowKeyV.resize(static_cast<std::size_t>(count));
      for (int row = 0; row < count; ++row) {
        const int k = basis.spanOrder()[static_cast<std::size_t>(first + row)];
        rowKeyU[static_cast<std::size_t>(row)] = basis.uKey(k);
        rowKeyV[static_cast<std::size_t>(row)] = basis.vKey(k);
      }
      const auto distinct = [](std::vector<int> keys) {
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        return keys;
      };
      keysU = distinct(rowKeyU);
      keysV = distinct(rowKeyV);
      gridU = static_cast<int>(keysU.size());
      gridV = static_cast<int>(keysV.size());
      if (static_cast<long long>(gridU) * gridV != count) return;
      gridRow.assign(static_cast<std::size_t>(count), -1);
      valuesU.resize(gridU, orderU);
      valuesV.resize(gridV, orderV);
      for (int row = 0; row < count; ++row) {
        const int iu = static_cast<int>(
            std::lower_bound(keysU.begin(), keysU.end(), rowKeyU[static_cast<std::size_t>(row)]) -
            keysU.begin());
        const int iv = static_cast<int>(
            std::lower_bound(keysV.begin(), keysV.end(), rowKeyV[static_cast<std::size_t>(row)]) -
            keysV.begin());
        int& slot = gridRow[static_cast<std::size_t>(iu * gridV + iv)];
        if (slot >= 0) return;  // two sensors at one grid point: not a grid
        slot = row;
        const int k = basis.spanOrder()[static_cast<std::size_t>(first + row)];
        for (int a = 0; a < orderU; ++a) valuesU(iu, a) = basis.uWeight(k, a);
        for (int b = 0; b < orderV; ++b) valuesV(iv, b) = basis.vWeight(k, b);
      }
      isGrid = true;
    };
    // Index of the pair (a, b), a <= b, among the pairs of n functions.
    const auto pairIndex = [](int n, int a, int b) { return a * n - a * (a - 1) / 2 + (b - a); };
    // The upper triangles of the weighted Gram matrices G_rc = W^T diag(S_rc) W of the group,
    // one per entry S(r, c), r <= c, of the rows of `entries`, into `upper`.
    //  - A grid of a tensor-product map: w = N (x) M, so G_rc((a, b), (a', b')) =
    //    sum_iu N_a N_a'(u_iu) sum_iv M_b M_b'(v_iv) S_rc(iu, iv), summed direction by direction
    //    over the pairs a <= a' and b <= b' (for bicubic patches and 10 x 10 sensors about a
    //    fifth of the products of the general sum).
    //  - Otherwise two dense products give the triangles of all entries at once: the columns
    //    b < h = order / 2 need only the rows a < h, the others all rows.
    const auto gramSums = [&](int order) {
      const int entryCount = d * (d + 1) / 2;
      // Only the pairs a <= b are written and read.
      upper.resize(static_cast<std::size_t>(entryCount * order * order));
      if (isGrid) {
        const int orderU = static_cast<int>(valuesU.cols());
        const int orderV = static_cast<int>(valuesV.cols());
        const int pairCountV = orderV * (orderV + 1) / 2;
        const auto products = [&](const Eigen::MatrixXd& values, Eigen::MatrixXd& pairs) {
          const int n = static_cast<int>(values.cols());
          pairs.resize(values.rows(), n * (n + 1) / 2);
          for (int a = 0; a < n; ++a) {
            for (int b = a; b < n; ++b) {
              pairs.col(pairIndex(n, a, b)) = values.col(a).cwiseProduct(values.col(b));
            }
          }
        };
        products(valuesU, pairsU);
        products(valuesV, pairsV);
        for (int e = 0; e < entryCount; ++e) {
          partial.setZero(pairCountV, gridU);
          for (int iu = 0; iu < gridU; ++iu) {
            for (int iv = 0; iv < gridV; ++iv) {
              const double value = entries(gridRow[static_cast<std::size_t>(iu * gridV + iv)], e);
              partial.col(iu) += value * pairsV.row(iv).transpose();
            }
          }
          tensorGram.noalias() = partial * pairsU;  // pairCountV x pairCountU
          for (int a = 0; a < order; ++a) {
            const int au = a / orderV, av = a % orderV;
            for (int b = a; b < order; ++b) {
              const int bu = b / orderV, bv = b % orderV;
              upper[static_cast<std::size_t>((a * order + b) * entryCount + e)] =
                  tensorGram(pairIndex(orderV, std::min(av, bv), std::max(av, bv)),
                             pairIndex(orderU, std::min(au, bu), std::max(au, bu)));
            }
          }
        }
        return;
      }
      const int low = order / 2, high = order - low;
      const int count = static_cast<int>(weights.rows());
      scaledLow.resize(count, entryCount * low);
      scaledHigh.resize(count, entryCount * high);
      for (int e = 0; e < entryCount; ++e) {
        for (int b = 0; b < order; ++b) {
          auto column = b < low ? scaledLow.col(e * low + b) : scaledHigh.col(e * high + b - low);
          column = weights.col(b).cwiseProduct(entries.col(e));
        }
      }
      gramLow.noalias() = weights.leftCols(low).transpose() * scaledLow;
      gramHigh.noalias() = weights.transpose() * scaledHigh;
      for (int e = 0; e < entryCount; ++e) {
        for (int b = 0; b < order; ++b) {
          for (int a = 0; a <= b; ++a) {
            upper[static_cast<std::size_t>((a * order + b) * entryCount + e)] =
                b < low ? gramLow(a, e * low + b) : gramHigh(a, e * high + b - low);
          }
        }
      }
    };
    // block = sum over the group's sensors of (w w^T) (x) S, right = sum of w (x) r, with S and
    // r the rows of `entries` (S(r, c), r <= c) and `rights`; the block mirrored from the
    // upper triangles of the Gram sums, so that it is exactly symmetric.
    const auto kroneckerSums = [&](int order, Eigen::MatrixXd& block, Eigen::VectorXd& right) {
      gramSums(order);
      // Entry S(r, c) of the symmetric d x d matrices, r <= c, is entry number entryOf[r][c].
      int entryOf[3][3] = {};
      for (int r = 0, entry = 0; r < d; ++r) {
        for (int c = r; c < d; ++c, ++entry) entryOf[r][c] = entryOf[c][r] = entry;
      }
      const int entryCount = d * (d + 1) / 2;
      block.resize(order * d, order * d);
      for (int b = 0; b < order; ++b) {
        for (int c = 0; c < d; ++c) {
          double* column = block.col(b * d + c).data();
          for (int a = 0; a < order; ++a) {
            const double* pair =
                upper.data() + (std::min(a, b) * order + std::max(a, b)) * entryCount;
            for (int r = 0; r < d; ++r) column[a * d + r] = pair[entryOf[r][c]];
          }
        }
      }
      const Eigen::MatrixXd sums = weights.transpose() * rights;  // order x d
      right.resize(order * d);
      for (int b = 0; b < order; ++b) {
        for (int r = 0; r < d; ++r) right[b * d + r] = sums(b, r);
      }
    };
    for (int i = range.begin(); i != range.end(); ++i) {
      if (!findRanks(i)) outsidePattern = true;
      const SensorTerms& set = setOf(i);
      const SensorMap& basis = *set.basis;
      const int g = groupList[static_cast<std::size_t>(i)].second;
      const int order = basis.order();
      const int blockSize = order * d;
      GroupSums& sum = sums[static_cast<std::size_t>(i)];
      const int first = basis.spanBegin()[static_cast<std::size_t>(g)];
      const int last = basis.spanBegin()[static_cast<std::size_t>(g) + 1];
      const int count = last - first;
      weights.resize(count, order);
      entries.resize(count, d * (d + 1) / 2);
      rights.resize(count, d);
      for (int j = first; j < last; ++j) {
        const int k = basis.spanOrder()[static_cast<std::size_t>(j)];
        const QuadraticForm& form = (*set.forms)[static_cast<std::size_t>(k)];
        const int row = j - first;
        for (int a = 0; a < order; ++a) weights(row, a) = basis.weight(k, a);
        int entry = 0;
        for (int r = 0; r < d; ++r) {
          rights(row, r) = form.b[r];
          for (int c = r; c < d; ++c) entries(row, entry++) = form.A(r, c);
        }
      }
      detectGrid(basis, first, last);
      kroneckerSums(order, sum.block, sum.right);
      sum.block *= set.weight;
      sum.right *= set.weight;
      if (set.rankOne == nullptr || set.rankOne->empty()) continue;
      // A term alpha (u . (x - x_now))^2 over the group's control points x: A += alpha u u^T,
      // b += alpha u (u . x_now).
      const RankOneTerms& rankOne = *set.rankOne;
      const int k0 = basis.spanOrder()[static_cast<std::size_t>(first)];
      if (rankOne.separable) {
        // u = w (x) t: per sensor S = sum alpha t t^T and r = S x_k (x_k = sum_j w_j x_now_j,
        // the sensor's point), summed like the forms.
        for (int j = first; j < last; ++j) {
          const int k = basis.spanOrder()[static_cast<std::size_t>(j)];
          const int row = j - first;
          Eigen::Vector3d point = Eigen::Vector3d::Zero();
          for (int a = 0; a < order; ++a) {
            point.head(d) += weights(row, a) *
                             controlPoints[static_cast<std::size_t>(basis.index(k0, a))].head(d);
          }
          Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
          for (int t = rankOne.start[static_cast<std::size_t>(k)];
               t < rankOne.start[static_cast<std::size_t>(k) + 1]; ++t) {
            Eigen::Vector3d direction = Eigen::Vector3d::Zero();
            for (int a = 0; a < d; ++a) {
              direction[a] = rankOne.vectors[static_cast<std::size_t>(t) * d + a];
            }
            S += rankOne.coefficients[static_cast<std::size_t>(t)] * direction *
                 direction.transpose();
          }
          const Eigen::Vector3d right = S * point;
          int entry = 0;
          for (int r = 0; r < d; ++r) {
            rights(row, r) = right[r];
            for (int c = r; c < d; ++c) entries(row, entry++) = S(r, c);
          }
        }
        kroneckerSums(order, sum.rankOneBlock, sum.rankOneRight);
      } else {
        int termCount = 0;
        for (int j = first; j < last; ++j) {
          const int k = basis.spanOrder()[static_cast<std::size_t>(j)];
          termCount += rankOne.start[static_cast<std::size_t>(k) + 1] -
                       rankOne.start[static_cast<std::size_t>(k)];
        }
        local.resize(blockSize);
        for (int a = 0; a < order; ++a) {
          local.segment(a * d, d) =
              controlPoints[static_cast<std::size_t>(basis.index(k0, a))].head(d);
        }
        // The group's vectors u (columns of U) and alpha u (columns of W), in sensor order:
        // sum alpha u u^T = U W^T and sum alpha u (u . x) = W U^T x.
        Eigen::MatrixXd U(blockSize, termCount);
        Eigen::MatrixXd W(blockSize, termCount);
        int column = 0;
        for (int j = first; j < last; ++j) {
          const int k = basis.spanOrder()[static_cast<std::size_t>(j)];
          for (int t = rankOne.start[static_cast<std::size_t>(k)];
               t < rankOne.start[static_cast<std::size_t>(k) + 1]; ++t, ++column) {
            U.col(column) = Eigen::Map<const Eigen::VectorXd>(
                rankOne.vectors.data() + static_cast<std::size_t>(t) * blockSize, blockSize);
            W.col(column) = rankOne.coefficients[static_cast<std::size_t>(t)] * U.col(column);
          }
        }
        sum.rankOneBlock.noalias() = U * W.transpose();
        sum.rankOneRight.noalias() = W * (U.transpose() * local);
      }
      sum.rankOneBlock *= set.weight;
      sum.rankOneRight *= set.weight;
    }
  });
  if (outsidePattern || patternStart_.empty()) {  // new sensor spans (or none yet): rebuild
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(ranks.size());
    for (int i = 0; i < groups; ++i) {
      const SensorMap& basis = *setOf(i).basis;
      const int k = firstSensor(i);
      for (int a = 0; a < basis.order(); ++a) {
        for (int b = 0; b < basis.order(); ++b) {
          pairs.emplace_back(basis.index(k, a), basis.index(k, b));
        }
      }
    }
    rebuildPattern(pairs);
    for (int i = 0; i < groups; ++i) findRanks(i);
  }

  // Scatter: each control point's column of the system and its rows of the right-hand side
  // gather their contributions in group order (a group adds once to each entry of a valid net),
  // so every entry sums the same way for any thread count. The columns are disjoint parts of
  // the value array, so they fill in parallel.
  const std::size_t nonZeros = static_cast<std::size_t>(system_.nonZeros());
  const int unknowns = controlPointCount_ * d;
  formValues_.assign(nonZeros, 0.0);
  rankOneValues_.assign(nonZeros, 0.0);
  formRight_ = Eigen::VectorXd::Zero(unknowns);
  rankOneRight_ = Eigen::VectorXd::Zero(unknowns);
  // (group, local index) of every appearance of each control point, in group order.
  std::vector<int> appearanceStart(static_cast<std::size_t>(controlPointCount_) + 1, 0);
  for (int i = 0; i < groups; ++i) {
    const SensorMap& basis = *setOf(i).basis;
    const int k = firstSensor(i);
    for (int a = 0; a < basis.order(); ++a) ++appearanceStart[basis.index(k, a) + 1];
  }
  for (int j = 0; j < controlPointCount_; ++j) {
    appearanceStart[static_cast<std::size_t>(j) + 1] +=
        appearanceStart[static_cast<std::size_t>(j)];
  }
  std::vector<std::pair<int, int>> appearances(static_cast<std::size_t>(appearanceStart.back()));
  {
    std::vector<int> next(appearanceStart.begin(), appearanceStart.end() - 1);
    for (int i = 0; i < groups; ++i) {
      const SensorMap& basis = *setOf(i).basis;
      const int k = firstSensor(i);
      for (int a = 0; a < basis.order(); ++a) {
        appearances[static_cast<std::size_t>(next[static_cast<std::size_t>(basis.index(k, a))]++)] =
            {i, a};
      }
    }
  }
  const auto scatterColumn = [&](int column) {
    const int row = column * d;
    for (int e = appearanceStart[static_cast<std::size_t>(column)];
         e < appearanceStart[static_cast<std::size_t>(column) + 1]; ++e) {
      const auto [i, b] = appearances[static_cast<std::size_t>(e)];
      const int order = setOf(i).basis->order();
      const GroupSums& sum = sums[static_cast<std::size_t>(i)];
      const bool withRankOne = sum.rankOneBlock.size() > 0;
      formRight_.segment(row, d) += sum.right.segment(b * d, d);
      if (withRankOne) rankOneRight_.segment(row, d) += sum.rankOneRight.segment(b * d, d);
      for (int a = 0; a < order; ++a) {
        const int rank =
            ranks[static_cast<std::size_t>(rankStart[static_cast<std::size_t>(i)] + a * order + b)];
        for (int c = 0; c < d; ++c) {
          for (int r = 0; r < d; ++r) {
            const std::size_t index = static_cast<std::size_t>(valueIndex(rank, column, r, c));
            formValues_[index] += sum.block(a * d + r, b * d + c);
            if (withRankOne) rankOneValues_[index] += sum.rankOneBlock(a * d + r, b * d + c);
          }
        }
      }
    }
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, controlPointCount_, 16),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int column = range.begin(); column != range.end(); ++column) {
                        scatterColumn(column);
                      }
                    });
  expansionPoint_ = stacked(controlPoints);
  assembled_ = true;
  for (Factorization& f : factorizations_) f.reset(false);  // a new system: none is reused
}

std::vector<Eigen::Vector3d> QuadraticModel::solveAssembled(double rankOneScale, double damping) {
  return *solveSystem(rankOneScale, damping, true);
}

std::optional<std::vector<Eigen::Vector3d>> QuadraticModel::minimizeAssembled(double rankOneScale,
                                                                              double damping) {
  return solveSystem(rankOneScale, damping, false);
}

std::optional<std::vector<Eigen::Vector3d>> QuadraticModel::solveSystem(double rankOneScale,
                                                                        double damping,
                                                                        bool indefiniteToo) {
  if (!assembled_) throw RuntimeFailure("the fitting model was solved before it was assembled");
  const SolveKey key{rankOneScale, damping, smoothingScale_, regularizerWeight_};
  for (int slot = 0; slot < 2; ++slot) {
    const Factorization& kept = factorizations_[static_cast<std::size_t>(slot)];
    if (kept.valid && kept.key == key) {  // a system already factorised: reuse it
      current_ = slot;
      rankOneScale_ = rankOneScale;
      if (!indefiniteToo && !kept.positiveDefinite) return std::nullopt;
      return unstacked(kept.solve(kept.residual));
    }
  }
  // A new factorisation goes to the slot that does not hold the last solve's.
  if (factorizations_[static_cast<std::size_t>(current_)].valid) current_ = 1 - current_;
  Factorization& f = factorizations_[static_cast<std::size_t>(current_)];
  const std::size_t nonZeros = formValues_.size();
  double* const values = system_.valuePtr();
  for (std::size_t e = 0; e < nonZeros; ++e) {
    values[e] = formValues_[e] + rankOneScale * rankOneValues_[e];
  }
  addScaled(smoothing_, smoothingIndices_, 1.0, values);
  addScaled(scaledSmoothing_, scaledSmoothingIndices_, smoothingScale_, values);
  rankOneScale_ = rankOneScale;
  // Gradient condition of m at c: (H + mu m0 I + R) c = r - H P.
  const Eigen::VectorXd right = formRight_ + rankOneScale * rankOneRight_;
  const Eigen::VectorXd residual = right - system_ * expansionPoint_;
  const int unknowns = controlPointCount_ * dimension_;
  double diagonalSum = 0.0;
  for (const int index : diagonalIndices_) diagonalSum += values[index];
  const double meanDiagonal = unknowns > 0 ? diagonalSum / unknowns : 0.0;
  const double ridge = (1e-12 + std::max(damping, 0.0)) * (meanDiagonal > 0.0 ? meanDiagonal : 1.0);
  for (const int index : diagonalIndices_) values[index] += ridge;
  if (regularizerWeight_ > 0.0 && regularizer_.nonZeros() > 0) {
    const double g0 = regularizer_.diagonal().mean();
    if (g0 > 0.0) {
      addScaled(regularizer_, regularizerIndices_,
                regularizerWeight_ * (meanDiagonal > 0.0 ? meanDiagonal : 1.0) / g0, values);
    }
  }
  f.valid = false;
  f.solverUsed = Solver::none;
  // Small systems whose pattern is dense anyway (closed surfaces with few control points, short
  // curves) are factorised densely: the simplicial factorisation's fill would make them slow.
  const bool dense = unknowns <= kDenseUnknowns &&
                     20.0 * static_cast<double>(system_.nonZeros()) >=
                         static_cast<double>(unknowns) * static_cast<double>(unknowns);
  if (dense) {
    // A blocked Cholesky factorisation when the system is positive definite (the common case),
    // else the pivoted LDLT, whose D tells the inertia.
    const Eigen::MatrixXd matrix(system_);
    f.denseCholesky.compute(matrix);
    if (f.denseCholesky.info() == Eigen::Success &&
        f.denseCholesky.matrixLLT().diagonal().allFinite() &&
        f.denseCholesky.matrixLLT().diagonal().minCoeff() > 0.0) {
      f.solverUsed = Solver::denseCholesky;
    } else {
      f.denseLdlt.compute(matrix);
      if (f.denseLdlt.info() == Eigen::Success && f.denseLdlt.vectorD().allFinite()) {
        f.solverUsed = Solver::denseLdlt;
      }
    }
  } else {
    if (unknowns > kSimplicialUnknowns) {
      if (!f.cholesky) f.cholesky = std::make_unique<SupernodalCholesky>();
      if (!f.analyzed) {
        f.cholesky->analyzePattern(system_);
        f.analyzed = true;
      }
      if (f.cholesky->factorize(system_)) f.solverUsed = Solver::supernodalCholesky;
    }
    // Small, or indefinite: the LDLT, which tells the inertia (not needed to learn only that a
    // large system is indefinite).
    if (f.solverUsed == Solver::none && (unknowns <= kSimplicialUnknowns || indefiniteToo)) {
      if (!f.ldltAnalyzed) {
        f.ldlt.analyzePattern(system_);
        f.ldltAnalyzed = true;
      }
      f.ldlt.factorize(system_);
      if (f.ldlt.info() == Eigen::Success) f.solverUsed = Solver::sparseLdlt;
    }
  }
  switch (f.solverUsed) {
    case Solver::none:
      f.positiveDefinite = false;
      break;
    case Solver::denseCholesky:
    case Solver::supernodalCholesky:
      f.positiveDefinite = true;
      break;
    case Solver::denseLdlt:
      f.positiveDefinite =
          f.denseLdlt.vectorD().size() == 0 || f.denseLdlt.vectorD().minCoeff() > 0.0;
      break;
    case Solver::sparseLdlt:
      f.positiveDefinite = f.ldlt.vectorD().size() == 0 || f.ldlt.vectorD().minCoeff() > 0.0;
      break;
  }
  if (!indefiniteToo && !f.positiveDefinite) return std::nullopt;
  if (f.solverUsed == Solver::none) {
    throw RuntimeFailure(
        "the fitting system could not be factorised (non-finite or indefinite "
        "quadratic forms)");
  }
  f.valid = true;
  f.key = key;
  f.residual = residual;
  const Eigen::VectorXd step = f.solve(residual);
  if ((f.solverUsed == Solver::sparseLdlt && f.ldlt.info() != Eigen::Success) ||
      !step.allFinite()) {
    throw RuntimeFailure("the fitting system could not be solved (non-finite step)");
  }
  return unstacked(step);
}

double QuadraticModel::predictedDecrease(const std::vector<Eigen::Vector3d>& step) const {
  if (!assembled_) return 0.0;
  // The Hessian of the last solve without ridge, damping and regulariser.
  std::vector<double> hessian(formValues_.size());
  for (std::size_t e = 0; e < hessian.size(); ++e) {
    hessian[e] = formValues_[e] + rankOneScale_ * rankOneValues_[e];
  }
  addScaled(smoothing_, smoothingIndices_, 1.0, hessian.data());
  addScaled(scaledSmoothing_, scaledSmoothingIndices_, smoothingScale_, hessian.data());
  const Eigen::Map<const Eigen::SparseMatrix<double>> H(system_.rows(), system_.cols(),
                                                        system_.nonZeros(), system_.outerIndexPtr(),
                                                        system_.innerIndexPtr(), hessian.data());
  const Eigen::VectorXd c = stacked(step);
  const Eigen::VectorXd gradientHalf =
      H * expansionPoint_ - (formRight_ + rankOneScale_ * rankOneRight_);
  return -(2.0 * gradientHalf.dot(c) + c.dot(H * c));
}

std::vector<Eigen::Vector3d> QuadraticModel::scaledSmoothingShift() const {
  const Factorization& f = factorizations_[static_cast<std::size_t>(current_)];
  if (!f.valid || scaledSmoothing_.nonZeros() == 0 || !assembled_) {
    return std::vector<Eigen::Vector3d>(static_cast<std::size_t>(controlPointCount_),
                                        Eigen::Vector3d::Zero());
  }
  const int d = dimension_;
  Eigen::VectorXd right(controlPointCount_ * d);
  Eigen::VectorXd coordinate(controlPointCount_);
  for (int a = 0; a < d; ++a) {
    for (int i = 0; i < controlPointCount_; ++i) coordinate[i] = expansionPoint_[i * d + a];
    const Eigen::VectorXd product = smoothingScale_ * (scaledSmoothing_ * coordinate);
    for (int i = 0; i < controlPointCount_; ++i) right[i * d + a] = product[i];
  }
  return unstacked(f.solve(right));
}

Eigen::VectorXd QuadraticModel::Factorization::solve(const Eigen::VectorXd& right) const {
  switch (solverUsed) {
    case Solver::denseCholesky:
      return denseCholesky.solve(right);
    case Solver::denseLdlt:
      return denseLdlt.solve(right);
    case Solver::supernodalCholesky:
      return cholesky->solve(right);
    case Solver::sparseLdlt:
      return ldlt.solve(right);
    case Solver::none:
      break;
  }
  throw RuntimeFailure("the fitting system was solved before it was factorised");
}

void QuadraticModel::Factorization::reset(bool pattern) {
  valid = false;
  solverUsed = Solver::none;
  if (pattern) {
    analyzed = false;
    ldltAnalyzed = false;
  }
}

Eigen::VectorXd QuadraticModel::stacked(const std::vector<Eigen::Vector3d>& controlPoints) const {
  const int d = dimension_;
  Eigen::VectorXd vector(controlPointCount_ * d);
  for (int i = 0; i < controlPointCount_; ++i) {
    vector.segment(i * d, d) = controlPoints[static_cast<std::size_t>(i)].head(d);
  }
  return vector;
}

std::vector<Eigen::Vector3d> QuadraticModel::unstacked(const Eigen::VectorXd& vector) const {
  const int d = dimension_;
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(controlPointCount_),
                                      Eigen::Vector3d::Zero());
  for (int i = 0; i < controlPointCount_; ++i) {
    points[static_cast<std::size_t>(i)].head(d) = vector.segment(i * d, d);
  }
  return points;
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
  for (const Eigen::SparseMatrix<double>* matrix :
       {&smoothing_, &scaledSmoothing_, &regularizer_}) {
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
  scaledSmoothingIndices_ = valueIndicesOf(scaledSmoothing_);
  regularizerIndices_ = valueIndicesOf(regularizer_);
  diagonalIndices_.clear();
  for (int j = 0; j < n; ++j) {
    for (int a = 0; a < d; ++a) diagonalIndices_.push_back(valueIndex(patternRank(j, j), j, a, a));
  }
  for (Factorization& f : factorizations_) f.reset(true);
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
                               const std::vector<int>& indices, double scale,
                               double* values) const {
  if (scale == 0.0) return;
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
  Eigen::VectorXd coordinate(controlPointCount_);
  for (int a = 0; a < dimension_; ++a) {
    for (int i = 0; i < controlPointCount_; ++i) {
      coordinate[i] = controlPoints[static_cast<std::size_t>(i)][a];
    }
    energy += coordinate.dot(smoothing_ * coordinate);
    if (smoothingScale_ != 0.0 && scaledSmoothing_.nonZeros() > 0) {
      energy += smoothingScale_ * coordinate.dot(scaledSmoothing_ * coordinate);
    }
  }
  return energy;
}

}  // namespace d2vdb::detail
