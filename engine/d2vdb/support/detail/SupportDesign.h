// Internal to the support module: the explicit least-squares design matrix of a support-function
// fit, for tests and benchmarks that compare the fitter's normal matrix against M^T M.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace d2vdb::detail {

/// The 3N x harmonicCount(degree) matrix M whose rows 3i, 3i+1, 3i+2 are the x, y, z components
/// of x_{Y_j}(n_i) = Y_j(n_i) n_i + grad_S Y_j(n_i) for every harmonic j: x_h(n_i) = M_i c.
/// `unitNormals` must be unit vectors.
Eigen::MatrixXd supportDesignMatrix(const std::vector<Eigen::Vector3d>& unitNormals, int degree);

}  // namespace d2vdb::detail
