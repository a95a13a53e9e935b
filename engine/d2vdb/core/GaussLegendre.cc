// Gauss-Legendre quadrature (GaussLegendre.h).
#include "d2vdb/core/GaussLegendre.h"

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

/// The derivative P'_count(x) of the Legendre polynomial of degree `count` (>= 1) at x in (-1, 1),
/// by the three-term recurrence; sets `value` to P_count(x).
double legendreDerivative(int count, double x, double& value) {
  double p0 = 1.0;
  double p1 = x;
  for (int n = 2; n <= count; ++n) {
    const double p2 = ((2.0 * n - 1.0) * x * p1 - (n - 1.0) * p0) / n;
    p0 = p1;
    p1 = p2;
  }
  value = p1;
  return count * (x * p1 - p0) / (x * x - 1.0);
}

}  // namespace

GaussLegendreRule gaussLegendreRule(int count) {
  if (count < 1 || count > 1000) {
    throw InputError("a Gauss-Legendre rule needs 1..1000 points, got " + std::to_string(count));
  }
  GaussLegendreRule rule;
  rule.nodes.assign(static_cast<std::size_t>(count), 0.0);
  rule.weights.assign(static_cast<std::size_t>(count), 0.0);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < count; ++i) {
    double x = std::cos(pi * (i + 0.75) / (count + 0.5));
    double value = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double slope = legendreDerivative(count, x, value);
      const double step = value / slope;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double derivative = legendreDerivative(count, x, value);
    rule.nodes[static_cast<std::size_t>(i)] = x;
    rule.weights[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
  return rule;
}

}  // namespace d2vdb
