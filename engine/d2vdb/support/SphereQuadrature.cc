#include "d2vdb/support/SphereQuadrature.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/GaussLegendre.h"
#include "d2vdb/core/MathConstants.h"

namespace d2vdb {
namespace {}  // namespace

SphereQuadrature sphereQuadrature(int exactDegree) {
  if (exactDegree < 0 || exactDegree > 400) {
    throw InputError("sphere quadrature degree " + std::to_string(exactDegree) +
                     " out of range (expected 0 to 400)");
  }
  const int zCount = (exactDegree + 2) / 2;
  const int phiCount = exactDegree + 1;
  const GaussLegendreRule zRule = gaussLegendreRule(zCount);
  const std::vector<double>& z = zRule.nodes;
  const std::vector<double>& zWeights = zRule.weights;
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
