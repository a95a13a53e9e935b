// Exact quadrature of polynomials over the unit sphere.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace d2vdb {

/// Nodes and weights of a product rule on S^2: Gauss-Legendre in z = cos(theta) times the
/// trapezoidal rule in phi. sum_i weights[i] f(nodes[i]) equals the integral of f over the sphere
/// (area element d omega, total 4 pi) exactly, up to rounding, for every polynomial f in
/// (x, y, z) of degree <= the `exactDegree` it was built for.
struct SphereQuadrature {
  std::vector<Eigen::Vector3d> nodes;  ///< unit vectors
  std::vector<double> weights;         ///< positive, summing to 4 pi
};

/// The product rule exact to polynomial degree `exactDegree` (0..400): ceil((exactDegree + 1) / 2)
/// Gauss-Legendre nodes in z times exactDegree + 1 equally spaced angles. Throws InputError outside
/// that range.
SphereQuadrature sphereQuadrature(int exactDegree);

}  // namespace d2vdb
