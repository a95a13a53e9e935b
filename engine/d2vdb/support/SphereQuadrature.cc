#include "d2vdb/support/SphereQuadrature.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n (Golub-Welsch would do
// too; Newton from the Chebyshev-like initial guesses converges in a few steps for every n).
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.assign(static_cast<std::size_t>(n), 0.0);
  weights.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0;
      double p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    // Final derivative at the converged node.
    double p0 = 1.0;
    double p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    derivative = n * (x * p1 - p0) / (x * x - 1.0);
    nodes[static_cast<std::size_t>(i)] = x;
    weights[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
}

}  // namespace

SphereQuadrature sphereQuadrature(int exactDegree) {
  if (exactDegree < 0 || exactDegree > 400) {
    throw InputError("sphere quadrature degree " + std::to_string(exactDegree) +
                     " out of range (expected 0 to 400)");
  }
  const int zCount = (exactDegree + 2) / 2;
  const int phiCount = exactDegree + 1;
  std::vector<double> z;
  std::vector<double> zWeights;
  gaussLegendre(zCount, z, zWeights);
  SphereQuadrature rule;
  rule.nodes.reserve(static_cast<std::size_t>(zCount * phiCount));
  rule.weights.reserve(static_cast<std::size_t>(zCount * phiCount));
  for (int i = 0; i < zCount; ++i) {
    const double zi = z[static_cast<std::size_t>(i)];
    const double rho = std::sqrt(std::max(0.0, 1.0 - zi * zi));
    for (int j = 0; j < phiCount; ++j) {
      const double phi = 2.0 * kPi * j / phiCount;
      rule.nodes.emplace_back(rho * std::cos(phi), rho * std::sin(phi), zi);
      rule.weights.push_back(zWeights[static_cast<std::size_t>(i)] * 2.0 * kPi / phiCount);
    }
  }
  return rule;
}

}  // namespace d2vdb
