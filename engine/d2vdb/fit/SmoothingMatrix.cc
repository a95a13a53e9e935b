#include "d2vdb/fit/SmoothingMatrix.h"

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"

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

void gaussLegendre(int count, std::vector<double>& nodes, std::vector<double>& weights) {
  if (count < 1 || count > 64) {
    throw InputError("Gauss-Legendre rule needs 1..64 points, got " + std::to_string(count));
  }
  nodes.assign(static_cast<std::size_t>(count), 0.0);
  weights.assign(static_cast<std::size_t>(count), 0.0);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < count; ++i) {
    // Newton on the Legendre polynomial P_count from the Chebyshev-like initial guess.
    double x = std::cos(pi * (i + 0.75) / (count + 0.5));
    double value = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double slope = legendreDerivative(count, x, value);
      const double step = value / slope;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double derivative = legendreDerivative(count, x, value);
    // Map from [-1, 1] to [0, 1].
    nodes[static_cast<std::size_t>(i)] = 0.5 * (1.0 - x);
    weights[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - x * x) * derivative * derivative);
  }
}

Eigen::SparseMatrix<double> derivativeGramMatrix(const BSplineCurve& curve, int derivativeOrder) {
  const int p = curve.degree();
  if (derivativeOrder < 1 || derivativeOrder > p) {
    throw InputError("smoothing derivative order must be 1.." + std::to_string(p) +
                     " for a degree-" + std::to_string(p) + " curve, got " +
                     std::to_string(derivativeOrder));
  }
  const KnotVector& knots = curve.knots();
  const double length = curve.domain().length();
  const double scale = std::pow(length, 2.0 * derivativeOrder - 1.0);
  std::vector<double> nodes;
  std::vector<double> weights;
  gaussLegendre(p + 1, nodes, weights);
  const int n = curve.controlPointCount();
  std::vector<Eigen::Triplet<double>> triplets;
  const std::vector<double> breaks = knots.breakpoints();
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    const ParameterInterval span{breaks[s], breaks[s + 1]};
    const int spanIndex = knots.findSpan(span.at(0.5));
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(p + 1, p + 1);
    for (std::size_t q = 0; q < nodes.size(); ++q) {
      const double t = span.at(nodes[q]);
      const BasisDerivatives d = basisDerivatives(knots, spanIndex, t, derivativeOrder);
      const Eigen::VectorXd row = d.row(derivativeOrder).transpose();
      block += (weights[q] * span.length()) * row * row.transpose();
    }
    for (int a = 0; a <= p; ++a) {
      for (int b = 0; b <= p; ++b) {
        triplets.emplace_back(curve.controlPointIndex(spanIndex - p + a),
                              curve.controlPointIndex(spanIndex - p + b), scale * block(a, b));
      }
    }
  }
  Eigen::SparseMatrix<double> gram(n, n);
  gram.setFromTriplets(triplets.begin(), triplets.end());
  return gram;
}

}  // namespace d2vdb
