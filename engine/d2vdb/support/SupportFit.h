// Least-squares fitting of a support function to oriented samples (Gravesen, Juettler, Sir,
// "Approximating offsets of surfaces by using the support function representation", 2008,
// section 3, "Least-squares fitting").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/support/SupportFunction.h"
#include "d2vdb/support/SupportSamples.h"

namespace d2vdb {

/// Default regularisation weight of fits over the whole sphere (see SupportFitOptions): too small
/// to move a fit whose samples cover the sphere, but it keeps the normal matrix definite when a
/// few directions are sampled sparsely.
inline constexpr double kDefaultSupportRegularization = 1e-10;

/// Default regularisation weight of fits over a patch's Gauss image: the harmonics are then only
/// sampled on part of the sphere and the penalty decides the function elsewhere.
inline constexpr double kPatchSupportRegularization = 1e-13;

/// Parameters of fitSupportFunction().
struct SupportFitOptions {
  /// Spherical-harmonic degree L (0..kMaxSupportDegree): (L + 1)^2 unknowns.
  int degree = 16;
  /// lambda >= 0. The fit minimises
  ///   (1/N) sum_i |X_i - x_h(n_i)|^2 + (lambda / 4 pi) integral_{S^2} h Delta(Delta + 2) h
  /// where the penalty equals (lambda / 4 pi) sum_lm (l - 1) l (l + 1) (l + 2) c_lm^2: a
  /// dimensionless smoothness (Sobolev) term on h that vanishes on degrees 0 and 1, so it never
  /// biases translations or offsets (fitting translated or offset samples changes only those
  /// coefficients, by exactly the translation or offset).
  double regularization = kDefaultSupportRegularization;
};

/// What fitSupportFunction() measured.
struct SupportFitReport {
  std::size_t samples = 0;
  int degree = 0;
  int unknowns = 0;             ///< (L + 1)^2
  double regularization = 0.0;  ///< lambda used
  double rmsResidual = 0.0;     ///< sqrt(mean |X_i - x_h(n_i)|^2), world units
  double maxResidual = 0.0;     ///< max |X_i - x_h(n_i)|
  std::size_t worstSample = 0;  ///< index of the sample with the largest residual
  double size = 0.0;            ///< diagonal of the samples' bounding box
  /// Reciprocal condition number (1-norm estimate) of the Jacobi-scaled normal matrix.
  double reciprocalCondition = 0.0;
  std::size_t renormalizedNormals = 0;  ///< normals off unit length by more than 1e-3
  double largestNormalDeviation = 0.0;  ///< max | |n_i| - 1 |
};

/// Fits h in the span of the harmonics of degree <= options.degree to the samples by linear least
/// squares on sum_i |X_i - x_h(n_i)|^2: three equations per sample (the normal component
/// X_i . n_i = h(n_i) and the two tangential components of X_i = grad_S h(n_i)).
///
/// Method: the normal matrix sum_i M_i^T M_i of the 3N x (L+1)^2 design matrix is formed without
/// building that matrix. With Y_i the harmonic values at n_i and the solid-harmonic extension,
/// M_i^T M_i = Y_i Y_i^T + J_i^T J_i - (Lambda Y_i)(Lambda Y_i)^T, where J_i = grad of the solid
/// harmonics = D Y'_i by exact ladder matrices D (at most two non-zeros per column) applied to the
/// harmonics Y' of one degree less and Lambda = diag(degree l_j) (Euler: n . grad = l on degree l).
/// So the whole normal matrix follows from the N x (L+1)^2 Gram matrix sum_i Y_i Y_i^T (one
/// symmetric rank-N update, a third of the work of M^T M and a sixth of a general product), plus
/// sparse products. Then Jacobi scaling and a Cholesky solve. The Gram matrix is accumulated over
/// fixed blocks of samples with a deterministic parallel reduction (TBB), so the result is bitwise
/// identical for any thread count.
///
/// Throws InputError (naming `sourceName`) for invalid samples (checkOrientedSamples), a degree
/// outside 0..kMaxSupportDegree, fewer samples than unknowns, a negative or non-finite
/// regularisation, or samples whose normals do not determine the coefficients (the normal matrix
/// is singular to working precision: e.g. all normals in one hemisphere at a high degree with no
/// regularisation).
SupportFunction fitSupportFunction(OrientedSamples samples, const SupportFitOptions& options = {},
                                   SupportFitReport* report = nullptr,
                                   const std::string& sourceName = "the samples");

}  // namespace d2vdb
