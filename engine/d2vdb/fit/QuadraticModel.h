// The quadratic model of one fitting iteration: assembly of the sensors' quadratic forms and the
// smoothing energy into a sparse symmetric system over the control points, and its solution.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <utility>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/SensorMap.h"

namespace d2vdb {

/// Minimises over control-point displacements c (n points, `dimension` coordinates each)
///   m(c) = (1/N) sum_k Q_k(x_k(P + c)) + sum_a (P + c)_a^T S (P + c)_a + mu * m0 * |c|^2
///          (+ the optional step regulariser, setStepRegularizer())
/// where Q_k are the sensors' quadratic forms (QuadraticForm: Q(x) = x^T A x - 2 b.x + c, world
/// units), x_k(P) the sensor positions of a SensorMap (curve or surface sensors), S the smoothing
/// matrix (n x n, e.g. lambda2 G2 + lambda1 G1 of SmoothingMatrix.h, or a surface's thin-plate
/// matrix), mu the relative damping and m0 the mean diagonal of the undamped system (so mu is
/// dimensionless). A ridge of 1e-12 m0 keeps the system
/// definite where no sensor and no smoothing acts. In 2D (dimension 2) only the xy blocks of the
/// forms enter and z stays 0.
///
/// Assembly runs in parallel over the sensor groups (knot spans of a curve, knot cells of a
/// surface); each group's sensors are summed in index order and the groups in group order, so
/// results are bitwise identical for any thread count. Solved with
/// Eigen's SimplicialLDLT. The system's sparsity pattern (control points sharing a sensor group,
/// plus the smoothing and regulariser patterns) is kept between solves, and with it the
/// fill-reducing ordering and symbolic factorisation: a solve whose sensors couple no new pair of
/// control points only scatters its blocks into the stored pattern and refactorises numerically.
class QuadraticModel {
 public:
  /// `smoothing` must be controlPointCount x controlPointCount, symmetric PSD. InputError for a
  /// dimension other than 2 or 3 or a smoothing matrix of the wrong size.
  QuadraticModel(int controlPointCount, int dimension, Eigen::SparseMatrix<double> smoothing);

  /// The minimising displacement c, one vector per control point (z = 0 in 2D). `forms` has one
  /// entry per sensor of `basis`. Throws RuntimeFailure if the factorisation fails (a non-finite
  /// form).
  std::vector<Eigen::Vector3d> solve(const SensorMap& basis,
                                     const std::vector<QuadraticForm>& forms,
                                     const std::vector<Eigen::Vector3d>& controlPoints,
                                     double damping);

  /// Adds the step regulariser rho * m0 / g0 * sum_a c_a^T R c_a to m(c), with R symmetric PSD
  /// (n x n; e.g. the bending Gram matrix, so that only rough displacements are damped and the
  /// minimiser of the fit is not biased) and g0 its mean diagonal. rho = 0 removes it.
  /// InputError for a wrong size or negative rho.
  void setStepRegularizer(Eigen::SparseMatrix<double> regularizer, double rho);

  /// sum_a P_a^T S P_a: the smoothing energy of the control points.
  double smoothingEnergy(const std::vector<Eigen::Vector3d>& controlPoints) const;

  int dimension() const { return dimension_; }

 private:
  /// Position in the control-point pattern of row i within column j, or -1 when absent.
  int patternRank(int row, int column) const;
  /// Rebuilds the pattern as the union of the current one, `pairs` (row, column of control
  /// points), the smoothing, the regulariser and the diagonal; the solver must re-analyse.
  void rebuildPattern(const std::vector<std::pair<int, int>>& pairs);
  /// Index into system_'s values of unknown (row * d + r, column * d + c), given the rank of row
  /// in the column.
  int valueIndex(int rank, int column, int r, int c) const {
    return static_cast<int>(system_.outerIndexPtr()[column * dimension_ + c]) + rank * dimension_ +
           r;
  }
  /// Value indices of every entry of `matrix` (an n x n matrix inside the pattern) for each
  /// coordinate, in `matrix`'s storage order: entry e, coordinate a at [e * d + a].
  std::vector<int> valueIndicesOf(const Eigen::SparseMatrix<double>& matrix) const;
  /// Adds scale * matrix (per coordinate) into system_'s values at `indices` (valueIndicesOf).
  void addScaled(const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& indices,
                 double scale);

  int controlPointCount_;
  int dimension_;
  Eigen::SparseMatrix<double> smoothing_;
  Eigen::SparseMatrix<double> regularizer_;
  double regularizerWeight_ = 0.0;
  // Control-point pattern (compressed columns, sorted rows) and the system over the unknowns
  // that expands it (each control-point entry becomes a d x d block).
  std::vector<int> patternStart_;
  std::vector<int> patternRows_;
  Eigen::SparseMatrix<double> system_;
  std::vector<int> smoothingIndices_;
  std::vector<int> regularizerIndices_;
  std::vector<int> diagonalIndices_;
  bool analyzed_ = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

}  // namespace d2vdb
