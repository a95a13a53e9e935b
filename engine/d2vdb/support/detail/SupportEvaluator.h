// Internal to the support module: the tables and kernels that evaluate a support function and its
// derivatives at many normals.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/support/SupportFunction.h"

namespace d2vdb::detail {

/// Normals are evaluated in blocks of this many (the last block padded), so a normal's result
/// depends only on that normal, never on how the work was split between threads.
inline constexpr int kSupportBlock = 64;

/// Quantities evaluated per normal, as rows of the product basis x table:
/// h, S1 = P - n . grad P, grad P (3), Hess P (xx, xy, xz, yy, yz; zz = -xx - yy since P is
/// harmonic), with P the solid-harmonic extension of h.
enum SupportQuantity : int {
  kValue = 0,
  kRadialDefect = 1,
  kGradX = 2,
  kGradY = 3,
  kGradZ = 4,
  kHessXX = 5,
  kHessXY = 6,
  kHessXZ = 7,
  kHessYY = 8,
  kHessYZ = 9,
  kQuantityCount = 10,
};

/// The evaluation tables of one support function.
struct SupportEvaluator {
  int degree = 0;
  /// harmonicCount(degree) x kQuantityCount: column q holds the coefficients of quantity q in the
  /// harmonic basis (zero beyond the degree that quantity needs).
  Eigen::MatrixXd table;

  SupportEvaluator(int degree, const Eigen::VectorXd& coefficients);

  /// The quantities at `count` (<= kSupportBlock) normals already normalised, into `result`
  /// (kSupportBlock x kQuantityCount, row i for normal i). `basis` is scratch of kSupportBlock x
  /// harmonicCount(degree). With `pointsOnly`, only kValue and the gradient are meaningful.
  void evaluateBlock(int count, const Eigen::Vector3d* normals, Eigen::MatrixXd& basis,
                     Eigen::MatrixXd& result, bool pointsOnly) const;
};

/// Assembles a SupportPoint from the quantities of one normal (row `row` of `result`).
SupportPoint assembleSupportPoint(const Eigen::Vector3d& normal, const Eigen::MatrixXd& result,
                                  Eigen::Index row);

/// An orthonormal tangent frame (e1, e2) of the unit vector n with (e1, e2, n) right-handed,
/// continuous except across n_z = 0 (Duff et al., "Building an Orthonormal Basis, Revisited",
/// JCGT 6(1), 2017).
void tangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2);

}  // namespace d2vdb::detail
