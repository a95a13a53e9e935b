// Gauss-Legendre quadrature on [-1, 1].
#pragma once

#include <vector>

namespace d2vdb {

/// The `count`-point Gauss-Legendre rule on [-1, 1]: int_-1^1 f(x) dx ~ sum_i weights[i]
/// f(nodes[i]), exact for polynomials of degree 2 count - 1. Nodes in decreasing order (from near
/// 1 to near -1), found by Newton's method on the Legendre polynomial P_count from Chebyshev-like
/// initial guesses, with the three-term recurrence; weights 2 / ((1 - x^2) P_count'(x)^2).
/// InputError for a count outside 1..1000.
struct GaussLegendreRule {
  std::vector<double> nodes;
  std::vector<double> weights;
};
GaussLegendreRule gaussLegendreRule(int count);

}  // namespace d2vdb
