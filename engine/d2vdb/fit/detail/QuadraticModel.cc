// The quadratic model of a fitting iteration: sensor forms assembled per span group into the
// normal equations, smoothing terms, and their sparse or dense solution.
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

/// Throws InputError when `set`'s forms or rank-one terms do not match its basis, or its basis
/// another control-point count than `controlPointCount`.
void requireMatching(const SensorTerms& set, int controlPointCount, int dimension) {
  if (set.basis == nullptr || set.forms == nullptr ||
      static_cast<int>(set.forms->size()) != set.basis->sensorCount() ||
      set.basis->controlPointCount() != controlPointCount) {
    throw InputError("a sensor set of the fitting model does not match its basis or net");
  }
  const RankOneTerms* rankOne = set.rankOne;
  if (rankOne != nullptr && !rankOne->empty() &&
      (rankOne->length != (rankOne->separable ? dimension : set.basis->order() * dimension) ||
       static_cast<int>(rankOne->start.size()) != set.basis->sensorCount() + 1 ||
       rankOne->vectors.size() != rankOne->coefficients.size() * rankOne->length ||
       rankOne->start.back() != static_cast<int>(rankOne->coefficients.size()))) {
    throw InputError("the rank-one terms of a sensor set do not match its basis");
  }
}

/// One span group of a sensor set: sensors basis.spanOrder()[first .. last), which all share the
/// control points of the first of them, `sensor`.
struct SpanGroup {
  const SensorTerms* set = nullptr;
  int first = 0;
  int last = 0;
  int sensor = 0;
};

/// Per span group: a dense block over its control points (the group's local unknowns a * d + r)
/// and the right-hand side, and the same for the rank-one terms (empty without them).
struct GroupSums {
  Eigen::MatrixXd block, rankOneBlock;
  Eigen::VectorXd right, rankOneRight;
};

/// Index of the pair (a, b), a <= b, among the pairs of n functions.
int pairIndex(int n, int a, int b) {
  return a * n - a * (a - 1) / 2 + (b - a);
}

/// A knot cell whose sensors form a full grid of countU x countV (u, v) parameters of a
/// tensor-product map (SensorMap::orderU()), and the Gram sums over it direction by direction.
class CellGrid {
 public:
  /// Whether the sensors basis.spanOrder()[first .. last) form such a grid; if so, remembers it.
  bool detect(const SensorMap& basis, int first, int last) {
    isGrid_ = false;
    const int orderU = basis.orderU();
    if (orderU <= 0) return false;
    const int orderV = basis.order() / orderU;
    const Eigen::Index count = last - first;
    rowKeyU_.resize(count);
    rowKeyV_.resize(count);
    for (Eigen::Index row = 0; row < count; ++row) {
      const int k = basis.spanOrder()[first + row];
      rowKeyU_[row] = basis.uKey(k);
      rowKeyV_[row] = basis.vKey(k);
    }
    keysU_ = distinct(rowKeyU_);
    keysV_ = distinct(rowKeyV_);
    countU_ = static_cast<Eigen::Index>(keysU_.size());
    countV_ = static_cast<Eigen::Index>(keysV_.size());
    if (countU_ * countV_ != count) return false;
    gridRow_.assign(count, -1);
    valuesU_.resize(countU_, orderU);
    valuesV_.resize(countV_, orderV);
    for (Eigen::Index row = 0; row < count; ++row) {
      const Eigen::Index iu = position(keysU_, rowKeyU_[row]);
      const Eigen::Index iv = position(keysV_, rowKeyV_[row]);
      Eigen::Index& slot = gridRow_[iu * countV_ + iv];
      if (slot >= 0) return false;  // two sensors at one grid point: not a grid
      slot = row;
      const int k = basis.spanOrder()[first + row];
      for (int a = 0; a < orderU; ++a) valuesU_(iu, a) = basis.uWeight(k, a);
      for (int b = 0; b < orderV; ++b) valuesV_(iv, b) = basis.vWeight(k, b);
    }
    isGrid_ = true;
    return true;
  }

  /// The upper triangles of G_e = W^T diag(entries.col(e)) W, W = N (x) M the sensors' basis
  /// values, into upper[(a * order + b) * entryCount + e] for a <= b: G_e((a, b), (a', b')) =
  /// sum_iu N_a N_a'(u_iu) sum_iv M_b M_b'(v_iv) S_e(iu, iv), summed over the pairs a <= a' and
  /// b <= b': for bicubic patches and 10 x 10 sensors about a fifth of the products of the
  /// general sum (BENCHMARKS.md, "Surface fitting goals", "Assembly by grid cells").
  void gramSums(const Eigen::MatrixXd& entries, int order, std::vector<double>& upper) {
    const int entryCount = static_cast<int>(entries.cols());
    const int orderU = static_cast<int>(valuesU_.cols());
    const int orderV = static_cast<int>(valuesV_.cols());
    const int pairCountV = orderV * (orderV + 1) / 2;
    pairProducts(valuesU_, pairsU_);
    pairProducts(valuesV_, pairsV_);
    for (int e = 0; e < entryCount; ++e) {
      partial_.setZero(pairCountV, countU_);
      for (Eigen::Index iu = 0; iu < countU_; ++iu) {
        for (Eigen::Index iv = 0; iv < countV_; ++iv) {
          const double value = entries(gridRow_[iu * countV_ + iv], e);
          partial_.col(iu) += value * pairsV_.row(iv).transpose();
        }
      }
      tensorGram_.noalias() = partial_ * pairsU_;  // pairCountV x pairCountU
      for (int a = 0; a < order; ++a) {
        const int au = a / orderV, av = a % orderV;
        for (int b = a; b < order; ++b) {
          const int bu = b / orderV, bv = b % orderV;
          upper[(a * order + b) * entryCount + e] =
              tensorGram_(pairIndex(orderV, std::min(av, bv), std::max(av, bv)),
                          pairIndex(orderU, std::min(au, bu), std::max(au, bu)));
        }
      }
    }
  }

  bool isGrid() const { return isGrid_; }

 private:
  static std::vector<int> distinct(std::vector<int> keys) {
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
  }
  static Eigen::Index position(const std::vector<int>& keys, int key) {
    return std::lower_bound(keys.begin(), keys.end(), key) - keys.begin();
  }
  /// pairs.col(pairIndex(n, a, b)) = values.col(a) .* values.col(b) for a <= b < n.
  static void pairProducts(const Eigen::MatrixXd& values, Eigen::MatrixXd& pairs) {
    const int n = static_cast<int>(values.cols());
    pairs.resize(values.rows(), n * (n + 1) / 2);
    for (int a = 0; a < n; ++a) {
      for (int b = a; b < n; ++b) {
        pairs.col(pairIndex(n, a, b)) = values.col(a).cwiseProduct(values.col(b));
      }
    }
  }

  bool isGrid_ = false;
  Eigen::Index countU_ = 0, countV_ = 0;
  /// gridRow_[iu * countV_ + iv]: the group's row of the sensor at (u_iu, v_iv).
  std::vector<Eigen::Index> gridRow_;
  std::vector<int> keysU_, keysV_, rowKeyU_, rowKeyV_;
  /// The u and v basis values of the grid's lines.
  Eigen::MatrixXd valuesU_, valuesV_;
  Eigen::MatrixXd pairsU_, pairsV_, partial_, tensorGram_;
};

/// Sums span groups into their GroupSums, one group after the other, with scratch space that it
/// keeps between groups (one per thread).
class GroupAssembler {
 public:
  GroupAssembler(int dimension, const std::vector<Eigen::Vector3d>& controlPoints)
      : d_(dimension), entryCount_(dimension * (dimension + 1) / 2), controlPoints_(controlPoints) {
    // Entry S(r, c) of the symmetric d x d matrices, r <= c, is entry number entryOf_[r][c].
    for (int r = 0, entry = 0; r < d_; ++r) {
      for (int c = r; c < d_; ++c, ++entry) entryOf_[r][c] = entryOf_[c][r] = entry;
    }
  }

  /// The weighted sums of `group`'s forms and rank-one terms.
  void sum(const SpanGroup& group, GroupSums& sum) {
    const SensorTerms& set = *group.set;
    loadForms(group);
    grid_.detect(*set.basis, group.first, group.last);
    kroneckerSums(sum.block, sum.right);
    sum.block *= set.weight;
    sum.right *= set.weight;
    if (set.rankOne == nullptr || set.rankOne->empty()) return;
    // A term alpha (u . (x - x_now))^2 over the group's control points x: A += alpha u u^T,
    // b += alpha u (u . x_now).
    if (set.rankOne->separable) {
      loadSeparableTerms(group);
      kroneckerSums(sum.rankOneBlock, sum.rankOneRight);
    } else {
      expandedTermSums(group, sum);
    }
    sum.rankOneBlock *= set.weight;
    sum.rankOneRight *= set.weight;
  }

 private:
  /// Row `row` of entries_ and rights_: the upper triangle of `matrix` and the first d entries of
  /// `right`.
  void setRow(Eigen::Index row, const Eigen::Matrix3d& matrix, const Eigen::Vector3d& right) {
    int entry = 0;
    for (int r = 0; r < d_; ++r) {
      rights_(row, r) = right[r];
      for (int c = r; c < d_; ++c) entries_(row, entry++) = matrix(r, c);
    }
  }

  /// Each sensor's basis weights, form matrix and form right-hand side, a row per sensor.
  void loadForms(const SpanGroup& group) {
    const SensorMap& basis = *group.set->basis;
    const std::vector<QuadraticForm>& forms = *group.set->forms;
    order_ = basis.order();
    const Eigen::Index count = group.last - group.first;
    weights_.resize(count, order_);
    entries_.resize(count, entryCount_);
    rights_.resize(count, d_);
    for (Eigen::Index row = 0; row < count; ++row) {
      const int k = basis.spanOrder()[group.first + row];
      for (int a = 0; a < order_; ++a) weights_(row, a) = basis.weight(k, a);
      setRow(row, forms[k].A, forms[k].b);
    }
  }

  /// Separable terms u = w (x) t: per sensor S = sum alpha t t^T and r = S x_k (x_k = sum_j w_j
  /// x_now_j, the sensor's point), into the rows of entries_ and rights_ to be summed like the
  /// forms.
  void loadSeparableTerms(const SpanGroup& group) {
    const SensorMap& basis = *group.set->basis;
    const RankOneTerms& rankOne = *group.set->rankOne;
    const std::size_t length = d_;  // entries per direction (std::size_t: t * length may pass int)
    for (Eigen::Index row = 0; row < weights_.rows(); ++row) {
      const int k = basis.spanOrder()[group.first + row];
      Eigen::Vector3d point = Eigen::Vector3d::Zero();
      for (int a = 0; a < order_; ++a) {
        point.head(d_) += weights_(row, a) * controlPoints_[basis.index(group.sensor, a)].head(d_);
      }
      Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
      for (int t = rankOne.start[k]; t < rankOne.start[k + 1]; ++t) {
        Eigen::Vector3d direction = Eigen::Vector3d::Zero();
        for (int a = 0; a < d_; ++a) direction[a] = rankOne.vectors[t * length + a];
        S += rankOne.coefficients[t] * direction * direction.transpose();
      }
      const Eigen::Vector3d right = S * point;
      setRow(row, S, right);
    }
  }

  /// General terms: the group's vectors u (columns of U) and alpha u (columns of W), in sensor
  /// order, give sum alpha u u^T = U W^T and sum alpha u (u . x) = W U^T x.
  void expandedTermSums(const SpanGroup& group, GroupSums& sum) {
    const SensorMap& basis = *group.set->basis;
    const RankOneTerms& rankOne = *group.set->rankOne;
    const int blockSize = order_ * d_;
    const std::size_t length = blockSize;  // std::size_t: t * length may pass int
    int termCount = 0;
    for (int j = group.first; j < group.last; ++j) {
      const int k = basis.spanOrder()[j];
      termCount += rankOne.start[k + 1] - rankOne.start[k];
    }
    local_.resize(blockSize);
    for (int a = 0; a < order_; ++a) {
      local_.segment(a * d_, d_) = controlPoints_[basis.index(group.sensor, a)].head(d_);
    }
    Eigen::MatrixXd U(blockSize, termCount);
    Eigen::MatrixXd W(blockSize, termCount);
    int column = 0;
    for (int j = group.first; j < group.last; ++j) {
      const int k = basis.spanOrder()[j];
      for (int t = rankOne.start[k]; t < rankOne.start[k + 1]; ++t, ++column) {
        U.col(column) =
            Eigen::Map<const Eigen::VectorXd>(rankOne.vectors.data() + t * length, blockSize);
        W.col(column) = rankOne.coefficients[t] * U.col(column);
      }
    }
    sum.rankOneBlock.noalias() = U * W.transpose();
    sum.rankOneRight.noalias() = W * (U.transpose() * local_);
  }

  /// The upper triangles of the weighted Gram matrices G_rc = W^T diag(S_rc) W of the group, one
  /// per entry S(r, c), r <= c, of the rows of entries_, into upper_ (only the pairs a <= b are
  /// written and read): on a grid direction by direction (CellGrid), otherwise by two dense
  /// products that give the triangles of all entries at once (the columns b < h = order / 2 need
  /// only the rows a < h, the others all rows).
  void gramSums() {
    upper_.resize(entryCount_ * order_ * order_);
    if (grid_.isGrid()) {
      grid_.gramSums(entries_, order_, upper_);
      return;
    }
    const int low = order_ / 2, high = order_ - low;
    scaledLow_.resize(weights_.rows(), entryCount_ * low);
    scaledHigh_.resize(weights_.rows(), entryCount_ * high);
    for (int e = 0; e < entryCount_; ++e) {
      for (int b = 0; b < order_; ++b) {
        auto column = b < low ? scaledLow_.col(e * low + b) : scaledHigh_.col(e * high + b - low);
        column = weights_.col(b).cwiseProduct(entries_.col(e));
      }
    }
    gramLow_.noalias() = weights_.leftCols(low).transpose() * scaledLow_;
    gramHigh_.noalias() = weights_.transpose() * scaledHigh_;
    for (int e = 0; e < entryCount_; ++e) {
      for (int b = 0; b < order_; ++b) {
        for (int a = 0; a <= b; ++a) {
          upper_[(a * order_ + b) * entryCount_ + e] =
              b < low ? gramLow_(a, e * low + b) : gramHigh_(a, e * high + b - low);
        }
      }
    }
  }

  /// block = sum over the group's sensors of (w w^T) (x) S, right = sum of w (x) r, with S and r
  /// the rows of entries_ and rights_; the block mirrored from the upper triangles of the Gram
  /// sums, so that it is exactly symmetric.
  void kroneckerSums(Eigen::MatrixXd& block, Eigen::VectorXd& right) {
    gramSums();
    block.resize(order_ * d_, order_ * d_);
    for (int b = 0; b < order_; ++b) {
      for (int c = 0; c < d_; ++c) {
        double* column = block.col(b * d_ + c).data();
        for (int a = 0; a < order_; ++a) {
          const double* pair =
              upper_.data() + (std::min(a, b) * order_ + std::max(a, b)) * entryCount_;
          for (int r = 0; r < d_; ++r) column[a * d_ + r] = pair[entryOf_[r][c]];
        }
      }
    }
    const Eigen::MatrixXd sums = weights_.transpose() * rights_;  // order x d
    right.resize(order_ * d_);
    for (int b = 0; b < order_; ++b) {
      for (int r = 0; r < d_; ++r) right[b * d_ + r] = sums(b, r);
    }
  }

  const int d_;
  const int entryCount_;  ///< entries of a symmetric d x d matrix
  const std::vector<Eigen::Vector3d>& controlPoints_;
  int entryOf_[3][3] = {};
  int order_ = 0;            ///< the current group's control points
  Eigen::MatrixXd weights_;  ///< sensors x order: each sensor's basis weights
  Eigen::MatrixXd entries_;  ///< sensors x d(d+1)/2: each sensor's symmetric d x d matrix
  Eigen::MatrixXd rights_;   ///< sensors x d: each sensor's right-hand side
  Eigen::MatrixXd scaledLow_, scaledHigh_, gramLow_, gramHigh_;
  Eigen::VectorXd local_;
  std::vector<double> upper_;  ///< the Gram values of one group, [(a * order + b) * E + e]
  CellGrid grid_;
};

/// The appearances of each control point in the span groups, as (group, local index) in group
/// order.
class ControlPointAppearances {
 public:
  using Appearance = std::pair<std::size_t, int>;

  ControlPointAppearances(const std::vector<SpanGroup>& groups, int controlPointCount)
      : start_(controlPointCount + 1, 0) {
    for (const SpanGroup& group : groups) {
      const SensorMap& basis = *group.set->basis;
      for (int a = 0; a < basis.order(); ++a) ++start_[basis.index(group.sensor, a) + 1];
    }
    for (std::size_t j = 1; j < start_.size(); ++j) start_[j] += start_[j - 1];
    appearances_.resize(start_.back());
    std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const SensorMap& basis = *groups[i].set->basis;
      for (int a = 0; a < basis.order(); ++a) {
        appearances_[next[basis.index(groups[i].sensor, a)]++] = {i, a};
      }
    }
  }

  /// Control point j's appearances: [begin(j), end(j)).
  const Appearance* begin(int j) const { return appearances_.data() + start_[j]; }
  const Appearance* end(int j) const { return appearances_.data() + start_[j + 1]; }

 private:
  std::vector<std::size_t> start_;
  std::vector<Appearance> appearances_;
};

}  // namespace

/// Every span group of every sensor set, in set order, with its sums and the places of its
/// (a, b) blocks in the pattern.
struct QuadraticModel::Assembly {
  Assembly(const std::vector<SensorTerms>& terms, int controlPointCount, int dimension) {
    for (const SensorTerms& set : terms) {
      requireMatching(set, controlPointCount, dimension);
      const std::vector<int>& begin = set.basis->spanBegin();
      for (std::size_t g = 0; g + 1 < begin.size(); ++g) {
        groups.push_back({&set, begin[g], begin[g + 1], set.basis->spanOrder()[begin[g]]});
      }
    }
    rankStart.assign(groups.size() + 1, 0);
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const int order = groups[i].set->basis->order();
      rankStart[i + 1] = rankStart[i] + order * order;
    }
    ranks.resize(rankStart.back());
    sums.resize(groups.size());
  }

  /// Every pair (a, b) of control points that share a group (with repetitions).
  std::vector<std::pair<int, int>> controlPointPairs() const {
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(ranks.size());
    for (const SpanGroup& group : groups) {
      const SensorMap& basis = *group.set->basis;
      for (int a = 0; a < basis.order(); ++a) {
        for (int b = 0; b < basis.order(); ++b) {
          pairs.emplace_back(basis.index(group.sensor, a), basis.index(group.sensor, b));
        }
      }
    }
    return pairs;
  }

  std::vector<SpanGroup> groups;
  std::vector<GroupSums> sums;
  /// Group i's (a, b) block goes to the rank ranks[rankStart[i] + a * order + b] of control
  /// point a's row in b's column of the pattern (-1 outside the stored pattern).
  std::vector<std::size_t> rankStart;
  std::vector<int> ranks;
};

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
  if (static_cast<int>(controlPoints.size()) != controlPointCount_) {
    throw InputError("the fitting model expects " + std::to_string(controlPointCount_) +
                     " control points, got " + std::to_string(controlPoints.size()));
  }
  Assembly assembly(terms, controlPointCount_, dimension_);
  std::atomic<bool> outsidePattern{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, assembly.groups.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      GroupAssembler assembler(dimension_, controlPoints);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (!findRanks(assembly, i)) outsidePattern = true;
                        assembler.sum(assembly.groups[i], assembly.sums[i]);
                      }
                    });
  if (outsidePattern || patternStart_.empty()) {  // new sensor spans (or none yet): rebuild
    rebuildPattern(assembly.controlPointPairs());
    for (std::size_t i = 0; i < assembly.groups.size(); ++i) findRanks(assembly, i);
  }
  scatter(assembly);
  expansionPoint_ = stacked(controlPoints);
  assembled_ = true;
  for (Factorization& f : factorizations_) f.reset(false);  // a new system: none is reused
}

bool QuadraticModel::findRanks(Assembly& assembly, std::size_t group) const {
  const SpanGroup& span = assembly.groups[group];
  const SensorMap& basis = *span.set->basis;
  const int order = basis.order();
  int* const ranks = assembly.ranks.data() + assembly.rankStart[group];
  bool found = true;
  for (int a = 0; a < order; ++a) {
    for (int b = 0; b < order; ++b) {
      const int rank = patternRank(basis.index(span.sensor, a), basis.index(span.sensor, b));
      found = found && rank >= 0;
      ranks[a * order + b] = rank;
    }
  }
  return found;
}

void QuadraticModel::scatter(const Assembly& assembly) {
  // Each control point's column of the system and its rows of the right-hand side gather their
  // contributions in group order (a group adds once to each entry of a valid net), so every entry
  // sums the same way for any thread count. The columns are disjoint parts of the value array, so
  // they fill in parallel.
  const int unknowns = controlPointCount_ * dimension_;
  formValues_.assign(system_.nonZeros(), 0.0);
  rankOneValues_.assign(system_.nonZeros(), 0.0);
  formRight_ = Eigen::VectorXd::Zero(unknowns);
  rankOneRight_ = Eigen::VectorXd::Zero(unknowns);
  const ControlPointAppearances appearances(assembly.groups, controlPointCount_);
  tbb::parallel_for(tbb::blocked_range<int>(0, controlPointCount_, 16),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int column = range.begin(); column != range.end(); ++column) {
                        for (const auto* at = appearances.begin(column);
                             at != appearances.end(column); ++at) {
                          scatterBlockColumn(assembly, at->first, at->second, column);
                        }
                      }
                    });
}

void QuadraticModel::scatterBlockColumn(const Assembly& assembly, std::size_t group, int b,
                                        int column) {
  const int d = dimension_;
  const int order = assembly.groups[group].set->basis->order();
  const GroupSums& sum = assembly.sums[group];
  const int* const ranks = assembly.ranks.data() + assembly.rankStart[group];
  const bool withRankOne = sum.rankOneBlock.size() > 0;
  const int row = column * d;
  formRight_.segment(row, d) += sum.right.segment(b * d, d);
  if (withRankOne) rankOneRight_.segment(row, d) += sum.rankOneRight.segment(b * d, d);
  for (int a = 0; a < order; ++a) {
    const int rank = ranks[a * order + b];
    for (int c = 0; c < d; ++c) {
      for (int r = 0; r < d; ++r) {
        const int index = valueIndex(rank, column, r, c);
        formValues_[index] += sum.block(a * d + r, b * d + c);
        if (withRankOne) rankOneValues_[index] += sum.rankOneBlock(a * d + r, b * d + c);
      }
    }
  }
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
  for (std::size_t slot = 0; slot < factorizations_.size(); ++slot) {
    const Factorization& kept = factorizations_[slot];
    if (kept.valid && kept.key == key) {  // a system already factorised: reuse it
      current_ = slot;
      rankOneScale_ = rankOneScale;
      if (!indefiniteToo && !kept.positiveDefinite) return std::nullopt;
      return unstacked(kept.solve(kept.residual));
    }
  }
  // A new factorisation goes to the slot that does not hold the last solve's.
  if (factorizations_[current_].valid) current_ = 1 - current_;
  Factorization& f = factorizations_[current_];
  const Eigen::VectorXd residual = loadSystem(rankOneScale, damping);
  f.factorize(system_, controlPointCount_ * dimension_, indefiniteToo);
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

void QuadraticModel::hessianValues(double rankOneScale, double* values) const {
  for (std::size_t e = 0; e < formValues_.size(); ++e) {
    values[e] = formValues_[e] + rankOneScale * rankOneValues_[e];
  }
  addScaled(smoothing_, smoothingIndices_, 1.0, values);
  addScaled(scaledSmoothing_, scaledSmoothingIndices_, smoothingScale_, values);
}

Eigen::VectorXd QuadraticModel::loadSystem(double rankOneScale, double damping) {
  double* const values = system_.valuePtr();
  hessianValues(rankOneScale, values);
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
  return residual;
}

void QuadraticModel::Factorization::factorize(const Eigen::SparseMatrix<double>& system,
                                              int unknowns, bool indefiniteToo) {
  valid = false;
  solverUsed = Solver::none;
  // Small systems whose pattern is dense anyway (closed surfaces with few control points, short
  // curves) are factorised densely: the simplicial factorisation's fill would make them slow.
  const bool dense = unknowns <= kDenseUnknowns &&
                     20.0 * static_cast<double>(system.nonZeros()) >=
                         static_cast<double>(unknowns) * static_cast<double>(unknowns);
  if (dense) {
    factorizeDense(system);
  } else {
    factorizeSparse(system, unknowns, indefiniteToo);
  }
  switch (solverUsed) {
    case Solver::none:
      positiveDefinite = false;
      break;
    case Solver::denseCholesky:
    case Solver::supernodalCholesky:
      positiveDefinite = true;
      break;
    case Solver::denseLdlt:
      positiveDefinite = denseLdlt.vectorD().size() == 0 || denseLdlt.vectorD().minCoeff() > 0.0;
      break;
    case Solver::sparseLdlt:
      positiveDefinite = ldlt.vectorD().size() == 0 || ldlt.vectorD().minCoeff() > 0.0;
      break;
  }
}

void QuadraticModel::Factorization::factorizeDense(const Eigen::SparseMatrix<double>& system) {
  // A blocked Cholesky factorisation when the system is positive definite (the common case),
  // else the pivoted LDLT, whose D tells the inertia.
  const Eigen::MatrixXd matrix(system);
  denseCholesky.compute(matrix);
  if (denseCholesky.info() == Eigen::Success && denseCholesky.matrixLLT().diagonal().allFinite() &&
      denseCholesky.matrixLLT().diagonal().minCoeff() > 0.0) {
    solverUsed = Solver::denseCholesky;
    return;
  }
  denseLdlt.compute(matrix);
  if (denseLdlt.info() == Eigen::Success && denseLdlt.vectorD().allFinite()) {
    solverUsed = Solver::denseLdlt;
  }
}

void QuadraticModel::Factorization::factorizeSparse(const Eigen::SparseMatrix<double>& system,
                                                    int unknowns, bool indefiniteToo) {
  if (unknowns > kSimplicialUnknowns) {
    if (!cholesky) cholesky = std::make_unique<SupernodalCholesky>();
    if (!analyzed) {
      cholesky->analyzePattern(system);
      analyzed = true;
    }
    if (cholesky->factorize(system)) solverUsed = Solver::supernodalCholesky;
  }
  // Small, or indefinite: the LDLT, which tells the inertia (not needed to learn only that a
  // large system is indefinite).
  if (solverUsed == Solver::none && (unknowns <= kSimplicialUnknowns || indefiniteToo)) {
    if (!ldltAnalyzed) {
      ldlt.analyzePattern(system);
      ldltAnalyzed = true;
    }
    ldlt.factorize(system);
    if (ldlt.info() == Eigen::Success) solverUsed = Solver::sparseLdlt;
  }
}

double QuadraticModel::predictedDecrease(const std::vector<Eigen::Vector3d>& step) const {
  if (!assembled_) return 0.0;
  // The Hessian of the last solve without ridge, damping and regulariser.
  std::vector<double> hessian(formValues_.size());
  hessianValues(rankOneScale_, hessian.data());
  const Eigen::Map<const Eigen::SparseMatrix<double>> H(system_.rows(), system_.cols(),
                                                        system_.nonZeros(), system_.outerIndexPtr(),
                                                        system_.innerIndexPtr(), hessian.data());
  const Eigen::VectorXd c = stacked(step);
  const Eigen::VectorXd gradientHalf =
      H * expansionPoint_ - (formRight_ + rankOneScale_ * rankOneRight_);
  return -(2.0 * gradientHalf.dot(c) + c.dot(H * c));
}

std::vector<Eigen::Vector3d> QuadraticModel::scaledSmoothingShift() const {
  const Factorization& f = factorizations_[current_];
  if (!f.valid || scaledSmoothing_.nonZeros() == 0 || !assembled_) {
    return std::vector<Eigen::Vector3d>(controlPointCount_, Eigen::Vector3d::Zero());
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
    vector.segment(i * d, d) = controlPoints[i].head(d);
  }
  return vector;
}

std::vector<Eigen::Vector3d> QuadraticModel::unstacked(const Eigen::VectorXd& vector) const {
  const int d = dimension_;
  std::vector<Eigen::Vector3d> points(controlPointCount_, Eigen::Vector3d::Zero());
  for (int i = 0; i < controlPointCount_; ++i) {
    points[i].head(d) = vector.segment(i * d, d);
  }
  return points;
}

int QuadraticModel::patternRank(int row, int column) const {
  if (patternStart_.empty()) return -1;
  const auto begin = patternRows_.begin() + patternStart_[column];
  const auto end = patternRows_.begin() + patternStart_[column + 1];
  const auto found = std::lower_bound(begin, end, row);
  return found != end && *found == row ? static_cast<int>(found - begin) : -1;
}

void QuadraticModel::rebuildPattern(const std::vector<std::pair<int, int>>& pairs) {
  const int n = controlPointCount_;
  const int d = dimension_;
  std::vector<std::vector<int>> columns(n);
  for (int j = 0; j < n; ++j) {
    std::vector<int>& rows = columns[j];
    rows.push_back(j);  // the ridge
    if (!patternStart_.empty()) {
      rows.insert(rows.end(), patternRows_.begin() + patternStart_[j],
                  patternRows_.begin() + patternStart_[j + 1]);
    }
  }
  for (const auto& [row, column] : pairs) columns[column].push_back(row);
  for (const Eigen::SparseMatrix<double>* matrix :
       {&smoothing_, &scaledSmoothing_, &regularizer_}) {
    for (int outer = 0; outer < matrix->outerSize(); ++outer) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(*matrix, outer); it; ++it) {
        columns[it.col()].push_back(static_cast<int>(it.row()));
      }
    }
  }
  patternStart_.assign(1, 0);
  patternRows_.clear();
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < n; ++j) {
    std::vector<int>& rows = columns[j];
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
  indices.reserve(matrix.nonZeros() * dimension_);
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
        values[indices[e * dimension_ + a]] += scale * it.value();
      }
    }
  }
}

double QuadraticModel::smoothingEnergy(const std::vector<Eigen::Vector3d>& controlPoints) const {
  double energy = 0.0;
  Eigen::VectorXd coordinate(controlPointCount_);
  for (int a = 0; a < dimension_; ++a) {
    for (int i = 0; i < controlPointCount_; ++i) {
      coordinate[i] = controlPoints[i][a];
    }
    energy += coordinate.dot(smoothing_ * coordinate);
    if (smoothingScale_ != 0.0 && scaledSmoothing_.nonZeros() > 0) {
      energy += smoothingScale_ * coordinate.dot(scaledSmoothing_ * coordinate);
    }
  }
  return energy;
}

}  // namespace d2vdb::detail
